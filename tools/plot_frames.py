#!/usr/bin/env python3
"""Particles coloured by body at chosen times of a run, side by side, in one PNG.

Usage: plot_frames.py RUN_DIR OUT.png --times 0.31 0.74 0.97 [--rotate DEG] [--title TEXT]
--rotate turns the picture (e.g. -45 shows a case computed in an inclined plane's frame, x down
the slope, as it stands in the world).
"""
import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import talus_frames

ap = argparse.ArgumentParser()
ap.add_argument("run")
ap.add_argument("out")
ap.add_argument("--times", type=float, nargs="+", required=True)
ap.add_argument("--rotate", type=float, default=0.0)
ap.add_argument("--title", default="")
a = ap.parse_args()
run = Path(a.run)
frames = talus_frames.times(run)
c, s = np.cos(np.radians(a.rotate)), np.sin(np.radians(a.rotate))
R = np.array([[c, -s], [s, c]])
fig, axes = plt.subplots(1, len(a.times), figsize=(4.2 * len(a.times), 4.2), squeeze=False)
colours = ["#9e9e9e", "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd"]
limits = None
for ax, t in zip(axes[0], a.times):
    tf, m = talus_frames.nearest(run, t, frames)
    x = m.points[:, :2] @ R.T
    body = m.point_data["body"].ravel().astype(int)
    if limits is None:
        limits = (x.min(0) - 0.1, x.max(0) + 0.1)
    for b in np.unique(body):
        sel = body == b
        ax.scatter(x[sel, 0], x[sel, 1], s=1.0, c=colours[b % len(colours)], linewidths=0)
    ax.set_title(f"t = {tf:.2f} s")
    ax.set_aspect("equal")
    ax.set_xlim(limits[0][0], limits[1][0])
    ax.set_ylim(limits[0][1], limits[1][1])
    ax.set_xlabel("x (m)")
axes[0][0].set_ylabel("y (m)")
if a.title:
    fig.suptitle(a.title)
fig.tight_layout()
fig.savefig(a.out, dpi=110)
print("wrote", a.out)
