#!/usr/bin/python3
"""Plots of a Talus run folder: energy and body velocities over time, probe speeds, and particle
snapshots coloured by body or by a field. Writes PNGs into RUN_DIR/plots/.

    tools/plot_run.py RUN_DIR [--field stress_yy|speed|plastic_strain|...] [--frames N]
"""
import argparse
import csv
import os
import sys
import tomllib
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import talus_frames  # noqa: E402


def read_csv(path):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return list(csv.DictReader(f))


def save(fig, path):
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=120, bbox_inches="tight")
    os.replace(tmp, path)
    plt.close(fig)
    print("wrote", path)


def plot_time_series(run, out):
    energy = read_csv(os.path.join(run, "energy.csv"))
    bodies = read_csv(os.path.join(run, "bodies.csv"))
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    if energy:
        ax1.plot([float(r["time"]) for r in energy], [float(r["kinetic_energy"]) for r in energy])
    ax1.set_ylabel("kinetic energy (J)")
    by_body = defaultdict(list)
    for r in bodies:
        by_body[r["body"]].append(r)
    for name, rows in by_body.items():
        ax2.plot([float(r["time"]) for r in rows], [float(r["mean_speed"]) for r in rows], label=name)
    ax2.set_xlabel("time (s)")
    ax2.set_ylabel("mass-averaged speed (m/s)")
    if by_body:
        ax2.legend()
    save(fig, os.path.join(out, "energy_and_speed.png"))

    probes = read_csv(os.path.join(run, "probes.csv"))
    if probes:
        by_probe = defaultdict(list)
        for r in probes:
            by_probe[r["probe"]].append(r)
        fig, ax = plt.subplots(figsize=(7, 4))
        for name, rows in by_probe.items():
            ax.plot([float(r["time"]) for r in rows], [float(r["speed"]) for r in rows], label=name)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("probe speed (m/s)")
        ax.legend()
        save(fig, os.path.join(out, "probes_speed.png"))


STRESS = ["xx", "yy", "zz", "xy", "yz", "xz"]


def available_fields(mesh):
    """What --field can name for this frame: body, speed, stress components, the stored arrays."""
    names = ["body"] + (["speed"] if "velocity" in mesh.point_data else [])
    if "stress" in mesh.point_data:
        names += [f"stress_{c}" for c in STRESS]
    return names + [n for n in mesh.point_data if n not in names]


def body_names(run):
    """The bodies' names in body order, from the run folder's case_as_run.toml."""
    try:
        with open(os.path.join(run, "case_as_run.toml"), "rb") as f:
            return [b["name"] for b in tomllib.load(f).get("body", [])]
    except (OSError, tomllib.TOMLDecodeError, KeyError):
        return []


def field_values(mesh, field):
    """A scalar per particle: body, speed, a stress component (stress_xx...), or a stored field."""
    pd = mesh.point_data
    if field == "speed":
        return np.linalg.norm(pd["velocity"], axis=1)
    if field.startswith("stress_"):
        comp = STRESS.index(field[7:])
        return pd["stress"][:, comp]
    values = pd[field]
    return values.ravel() if values.ndim == 1 or values.shape[1] == 1 else np.linalg.norm(values, axis=1)


def plot_snapshots(run, out, field, count, log=False):
    pvd = os.path.join(run, "particles.pvd")
    if not os.path.exists(pvd):
        return
    frames = talus_frames.times(run)
    if not frames:
        return
    if count == 1:  # one snapshot: the final state
        picks = [len(frames) - 1]
    else:
        picks = sorted(set(np.linspace(0, len(frames) - 1, min(count, len(frames))).round().astype(int)))
    names = body_names(run)
    for i in picks:
        t, files = frames[i]
        mesh = talus_frames.read(run, files)
        if field not in available_fields(mesh):
            print(f"error: no field '{field}' in {', '.join(files)}; the fields are: "
                  + ", ".join(available_fields(mesh)), file=sys.stderr)
            sys.exit(2)
        fig, ax = plt.subplots(figsize=(8, 5))
        values = field_values(mesh, field)
        size = max(0.2, 2e4 / len(values))
        if field == "body":  # categories: one colour and a legend entry per body
            cmap = plt.get_cmap("tab10")
            for b in np.unique(values).astype(int):
                at = values == b
                label = names[b] if b < len(names) else f"body {b}"
                ax.scatter(mesh.points[at, 0], mesh.points[at, 1], s=size, lw=0,
                           color=cmap(b % 10), label=label)
            ax.legend(markerscale=max(1.0, 6.0 / size ** 0.5), loc="best")
        else:
            if log:
                values = np.log10(np.maximum(values, 1e-6))
            sc = ax.scatter(mesh.points[:, 0], mesh.points[:, 1], c=values, s=size, lw=0,
                            cmap="viridis")
            fig.colorbar(sc, ax=ax, label=f"log10 {field}" if log else field)
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.set_title(f"t = {t:.3g} s")
        save(fig, os.path.join(out, f"snapshot_{field}_{i:04d}.png"))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("--field", default="body", help="body, speed, stress_yy, plastic_strain, ...")
    ap.add_argument("--frames", type=int, default=4, help="number of snapshots (1: the final state)")
    ap.add_argument("--log", action="store_true", help="colour by log10 of the field")
    args = ap.parse_args()
    out = os.path.join(args.run, "plots")
    os.makedirs(out, exist_ok=True)
    plot_time_series(args.run, out)
    plot_snapshots(args.run, out, args.field, args.frames, args.log)


if __name__ == "__main__":
    main()
