#!/usr/bin/env python3
"""Displacement along the plane against time for the rolling-disk and sliding-block benchmarks,
with their closed forms (issue 4), from the run folders of `talus verify`.

    build/release/talus verify --quick --cases rolling_disk_45 rolling_disk_60 sliding_block \
        sliding_block_deformable --out /tmp/verif
    /usr/bin/python3 tools/plot_contact_benchmarks.py /tmp/verif docs/img/contact_benchmarks.png

Talus is drawn at the runs' output times (markers), the closed form as a line of the same colour:
a cylinder rolls, x = g t^2 sin / 3, while tan <= 3 mu, else slips, x = g t^2 (sin - mu cos) / 2;
a block slides, x = g t^2 (sin - mu cos) / 2.
"""
import csv
import math
import sys
import tomllib
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def pair_friction(case):
    """Friction of the first [[contact]] entry that names a pair (the one the checks set)."""
    for c in case.get("contact", []):
        if "bodies" in c:
            return float(c["friction"])
    raise ValueError("no [[contact]] entry with bodies")


def along_plane(folder, body, direction):
    rows = [r for r in csv.DictReader(open(folder / "bodies.csv")) if r["body"] == body]
    t = np.array([float(r["time"]) for r in rows])
    x = np.array([[float(r["centroid_x"]), float(r["centroid_y"])] for r in rows])
    n = np.asarray(direction, dtype=float)
    return t, (x - x[0]) @ (n / np.linalg.norm(n))


def runs(out, stem):
    """Run folders of one case: stem, or stem_0, stem_1, ..."""
    base = Path(out) / "runs"
    single = base / stem
    if single.is_dir():
        return [single]
    return sorted(base.glob(f"{stem}_[0-9]*"), key=lambda p: int(p.name.rsplit("_", 1)[1]))


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    out, target = Path(sys.argv[1]), Path(sys.argv[2])
    g = 9.81
    fig, grid = plt.subplots(2, 3, figsize=(15, 8.2), height_ratios=[3, 2])
    axes, errs = grid[0], grid[1]
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]

    ax = axes[0]
    k = 0
    for stem, degrees in (("rolling_disk_60", 60.0), ("rolling_disk_45", 45.0)):
        theta = math.radians(degrees)
        direction = (math.cos(theta), -math.sin(theta))
        for folder in runs(out, stem):
            case = tomllib.loads((folder / "case_as_run.toml").read_text())
            mu = pair_friction(case)
            t, x = along_plane(folder, "disk", direction)
            rolls = math.tan(theta) <= 3 * mu
            a = g * math.sin(theta) / 1.5 if rolls else g * (math.sin(theta) - mu * math.cos(theta))
            tt = np.linspace(0, t[-1], 100)
            c = colours[k % len(colours)]
            ax.plot(tt, 0.5 * a * tt**2, "-", color=c, lw=1)
            err = 100 * (x[-1] / (0.5 * a * t[-1] ** 2) - 1)
            ax.plot(t, x, "o", color=c, ms=5,
                    label=f"{degrees:.0f} deg, mu {mu:g} ({'rolls' if rolls else 'slips'}): "
                          f"{err:+.2f} % at {t[-1]:g} s")
            errs[0].plot(t[1:], 100 * (x[1:] / (0.5 * a * t[1:] ** 2) - 1), "o-", color=c, ms=5)
            k += 1
    ax.set_title("Rolling disk (cylinder) on a rigid plane")

    for ax, err_ax, stem, title in ((axes[1], errs[1], "sliding_block",
                                     "Sliding block, rigid plane"),
                                    (axes[2], errs[2], "sliding_block_deformable",
                                     "Sliding block, deformable plane")):
        theta = math.radians(30.0)
        direction = (math.cos(theta), -math.sin(theta))
        for k, folder in enumerate(runs(out, stem)):
            case = tomllib.loads((folder / "case_as_run.toml").read_text())
            mu = pair_friction(case)
            t, x = along_plane(folder, "block", direction)
            a = g * (math.sin(theta) - mu * math.cos(theta))
            tt = np.linspace(0, t[-1], 100)
            c = colours[k % len(colours)]
            ax.plot(tt, 0.5 * a * tt**2, "-", color=c, lw=1)
            worst = max((abs(xi / (0.5 * a * ti**2) - 1) for ti, xi in zip(t, x) if ti > 0),
                        default=0.0)
            ax.plot(t, x, "o", color=c, ms=5,
                    label=f"mu {mu:g}: largest error {100 * worst:.2f} %")
            err_ax.plot(t[1:], 100 * (x[1:] / (0.5 * a * t[1:] ** 2) - 1), "o-", color=c, ms=5)
        ax.set_title(title)

    for ax in axes:
        ax.plot([], [], "-", color="grey", lw=1, label="closed form (lines)")
        ax.plot([], [], "o", color="grey", ms=5, label="Talus (markers)")
        ax.set_xlabel("time (s)")
        ax.set_ylabel("centroid displacement along the plane (m)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7.5, loc="upper left")
    for ax, limit, when in zip(errs, (2.0, 0.5, 0.5), ("at 1 s", "at every time", "at every time")):
        ax.axhspan(-limit, limit, color="green", alpha=0.08,
                   label=f"issue 4's limit, {limit:g} % {when}")
        ax.axhline(0.0, color="grey", lw=0.8)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("error against the closed form (%)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7.5, loc="lower right")
    fig.tight_layout()
    tmp = target.with_name(target.name + ".tmp.png")
    fig.savefig(tmp, dpi=90)
    tmp.replace(target)
    print(f"wrote {target}")


if __name__ == "__main__":
    main()
