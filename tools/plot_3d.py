#!/usr/bin/env python3
"""Pictures of a 3D run folder (matplotlib, no display needed):
  3d_frames.png   the bodies in perspective at the given times, deformable bodies coloured by
                  their displacement, rigid ones grey
  3d_section.png  a slice one particle spacing thick at the same times, as the 2D cases are
                  drawn: across y at the middle of the grid, or at --cut x=VALUE / y=VALUE
                  (the lattice row nearest it)
  3d_lake.png     with a fluid body (--lake, default "lake"; its frames need the mass and volume
  lake.json       fields): the water that has left the run through each outflow face over time
                  (its particles an outflow face emptied: they lie on that face and keep their
                  volume), the run-up probes of summary.json, and with --past AXIS=VALUE the
                  water past that plane (below VALUE along AXIS, those left through a face
                  there included: the water over a dam whose downstream face is at VALUE), each
                  particle at its volume in the first frame (the frames need the id field)

Usage: plot_3d.py RUN_DIR [--times T ...] [--out DIR] [--every N] [--cut AXIS=VALUE] [--azim DEG]
                  [--past AXIS=VALUE]
"""
import argparse
import tomllib
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import talus_frames  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("run")
ap.add_argument("--times", type=float, nargs="+", default=[0.0, 15.0, 45.0])
ap.add_argument("--out")
ap.add_argument("--every", type=int, default=4, help="draw every Nth particle in perspective")
ap.add_argument("--cut", help="the slice: x=VALUE or y=VALUE (default: y at the grid's middle)")
ap.add_argument("--azim", type=float, default=-60.0, help="perspective azimuth (degrees)")
ap.add_argument("--lake", default="lake", help="the fluid body, if the run has one")
ap.add_argument("--past", help="AXIS=VALUE: also the water below VALUE along x, y or z")
a = ap.parse_args()
run = Path(a.run)
out = Path(a.out) if a.out else run / "plots"
out.mkdir(parents=True, exist_ok=True)
frames = talus_frames.times(run)
case = tomllib.loads((run / "case_as_run.toml").read_text())
rigid = {i for i, b in enumerate(case["body"]) if b.get("rigid", False)}
names = [b["name"] for b in case["body"]]
lake = names.index(a.lake) if a.lake in names else None


def frame(t):
    return talus_frames.nearest(run, t, frames)


shots = [frame(t) for t in a.times]
fig = plt.figure(figsize=(6 * len(shots), 5))
for k, (tf, m) in enumerate(shots):
    ax = fig.add_subplot(1, len(shots), k + 1, projection="3d")
    x = m.points
    body = m.point_data["body"].ravel().astype(int)
    disp = np.linalg.norm(m.point_data["displacement"], axis=1) if "displacement" in m.point_data \
        else np.zeros(len(x))
    sel = np.arange(len(x)) % a.every == 0
    hard = sel & np.isin(body, list(rigid))
    water = sel & (body == lake)
    soft = sel & ~np.isin(body, list(rigid)) & ~water
    ax.scatter(x[hard, 0], x[hard, 1], x[hard, 2], s=0.2, c="#bbbbbb", linewidths=0)
    ax.scatter(x[water, 0], x[water, 1], x[water, 2], s=0.6, c="#3a7bd5", linewidths=0)
    sc = ax.scatter(x[soft, 0], x[soft, 1], x[soft, 2], s=0.4 if soft.sum() > 20000 else 3.0, c=disp[soft], cmap="viridis",
                    vmin=0, vmax=max(1.0, disp.max()), linewidths=0)
    ax.set_title(f"t = {tf:.1f} s")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    ax.set_box_aspect(np.ptp(x, axis=0))
    ax.view_init(elev=25, azim=a.azim)
fig.colorbar(sc, ax=fig.axes, shrink=0.6, label="displacement (m)")
fig.savefig(out / "3d_frames.png", dpi=110)
plt.close(fig)

fig, axes = plt.subplots(1, len(shots), figsize=(5 * len(shots), 3.2), squeeze=False)
for k, (tf, m) in enumerate(shots):
    x = m.points
    body = m.point_data["body"].ravel().astype(int)
    spacing = case["grid"]["cell_size"] / case["body"][0].get("particles_per_cell", 2)
    axis, across = (0, 1) if a.cut and a.cut.startswith("x=") else (1, 0)
    o = case["grid"].get("origin", [0, 0, 0])[axis]
    at = float(a.cut[2:]) - o if a.cut else 0.5 * case["grid"]["extent"][axis]
    mid = o + (np.floor(at / spacing) + 0.5) * spacing  # the lattice row nearest the cut
    cut = np.abs(x[:, axis] - mid) < 0.5 * spacing
    ax = axes[0][k]
    ax.scatter(x[cut, across], x[cut, 2], s=1, c=np.where(np.isin(body[cut], list(rigid)), 0.8, 0.2),
               cmap="gray", vmin=0, vmax=1, linewidths=0)
    wet = cut & (body == lake)
    ax.scatter(x[wet, across], x[wet, 2], s=1, c="#3a7bd5", linewidths=0)
    ax.set_title(f"t = {tf:.1f} s, slice {'xy'[axis]} = {mid:.0f} m")
    ax.set_aspect("equal")
    ax.set_xlabel(f"{'xy'[across]} (m)")
    ax.set_ylabel("z (m)")
fig.tight_layout()
fig.savefig(out / "3d_section.png", dpi=110)
plt.close(fig)
print("wrote", out / "3d_frames.png", out / "3d_section.png")

# The water that left through each outflow face of the grid: the lake's particles an outflow face
# emptied (no mass) lie on that face and keep their volume at the crossing.
if lake is not None:
    import json
    g = case["grid"]
    origin = np.array(g.get("origin", [0.0, 0.0, 0.0]), dtype=float)
    top = origin + np.array(g["extent"], dtype=float)
    faces = {f"{'xyz'[d]}_{side}": (d, side) for d in range(3) for side in ("min", "max")
             if g.get("boundary", {}).get(f"{'xyz'[d]}_{side}") == "outflow"}
    series = {f: [] for f in faces}
    past_axis, past_at = ("xyz".index(a.past.split("=")[0]), float(a.past.split("=")[1])) \
        if a.past else (None, None)
    past = []
    times, total = [], None
    for t, f in frames:
        m = talus_frames.read(run, f)
        if "mass" not in m.point_data or "volume" not in m.point_data:
            raise SystemExit(f"plot_3d.py: {f} lacks the mass or volume field ([output] fields)")
        w = m.point_data["body"].ravel().astype(int) == lake
        vol = m.point_data["volume"].ravel()
        empty = w & (m.point_data["mass"].ravel() == 0.0)
        if total is None:
            total = float(vol[w].sum())
        times.append(t)
        for name, (d, side) in faces.items():
            at = top[d] if side == "max" else origin[d]
            # On the face within the frames' position rounding (a 2,000th of a cell).
            on = empty & (np.abs(m.points[:, d] - at) <= max(1e-6 * max(1.0, abs(at)),
                                                            g["cell_size"] / 1000))
            series[name].append(float(vol[on].sum()))
        if past_axis is not None:  # at each particle's first volume: a falling jet's J is not
            if "id" not in m.point_data:  # the water's volume
                raise SystemExit(f"plot_3d.py: {f} lacks the id field (--past needs it)")
            ids = m.point_data["id"].ravel().astype(np.int64)
            if not past:
                volume0 = dict(zip(ids[w].tolist(), vol[w].tolist()))
            beyond = w & (m.points[:, past_axis] < past_at)
            past.append(float(sum(volume0.get(i, 0.0) for i in ids[beyond].tolist())))
    summary = json.loads((run / "summary.json").read_text())
    result = {"lake_volume_m3": total, "time_s": times, "left_through_m3": series,
              "left_at_end_m3": {k: v[-1] for k, v in series.items()},
              "run_up": summary.get("results", {}).get("run_up", {})}
    if past_axis is not None:
        result.update({"past": a.past, "past_m3": past, "past_at_end_m3": past[-1],
                       "past_max_m3": max(past)})
    (out / "lake.json").write_text(json.dumps(result, indent=1))
    fig, ax = plt.subplots(figsize=(6, 3.5))
    for name, v in series.items():
        ax.plot(times, np.array(v) / 1e6, label=f"through {name}")
    if past_axis is not None:
        ax.plot(times, np.array(past) / 1e6, "k--", label=f"past {a.past}")
    ax.set_xlabel("time since release (s)")
    ax.set_ylabel("water that left (million m$^3$)")
    ax.set_title(f"the lake: {total / 1e6:.1f} million m$^3$")
    if series or past:
        ax.legend()
    fig.tight_layout()
    fig.savefig(out / "3d_lake.png", dpi=110)
    plt.close(fig)
    print("wrote", out / "3d_lake.png", out / "lake.json", result["left_at_end_m3"],
          f"past {a.past}: {past[-1]:.0f} m^3 at the end" if past else "")
