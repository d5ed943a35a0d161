#!/usr/bin/env python3
"""Writes the elevation rasters (ESRI ASCII grids, which GDAL reads) that Talus's terrain cases
ship:

  plane OUT.asc --slope DEG --extent X Y --cell H --height Z0
      the plane z = Z0 - x tan(slope) over [0, X] x [0, Y] (cases/benchmarks/terrain_block.toml)

  section SECTION.csv LINE[,LINE...] OUT.asc --width W --cell H [--flank DEG --flank-width B]
      a 2D section's line z(x) (section.csv's `line,x,z` rows, e.g. ground_before or
      failure_surface; with several, each x takes the first line that reaches it) extruded
      across the valley along y over [0, W]; with --flank, the surface
      rises at DEG degrees over the last B metres on either side (a valley whose flanks close the
      slide in) (cases/vaiont/3d/)

Each cell holds the surface at its centre; the grid's south-west corner is the origin.
"""
import argparse
import csv
import math

import numpy as np


def write_asc(path, z, x0, y0, cell):
    """z[j, i]: j along y from the south; ESRI ASCII lists the northern row first."""
    ny, nx = z.shape
    with open(path, "w") as f:
        f.write(f"ncols {nx}\nnrows {ny}\nxllcorner {x0}\nyllcorner {y0}\ncellsize {cell}\n"
                "NODATA_value -9999\n")
        for row in z[::-1]:
            f.write(" ".join(f"{v:.4f}" for v in row) + "\n")


def centres(length, cell):
    n = int(math.ceil(length / cell - 1e-9))  # the cells cover the whole length
    return (np.arange(n) + 0.5) * cell


ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
sub = ap.add_subparsers(dest="kind", required=True)
p = sub.add_parser("plane")
p.add_argument("out")
p.add_argument("--slope", type=float, required=True)
p.add_argument("--extent", type=float, nargs=2, required=True)
p.add_argument("--cell", type=float, required=True)
p.add_argument("--height", type=float, required=True)
s = sub.add_parser("section")
s.add_argument("section")
s.add_argument("line")
s.add_argument("out")
s.add_argument("--width", type=float, required=True)
s.add_argument("--cell", type=float, required=True)
s.add_argument("--flank", type=float, default=0.0, help="flank slope (degrees), 0: none")
s.add_argument("--flank-width", type=float, default=0.0)
a = ap.parse_args()

if a.kind == "plane":
    x, y = centres(a.extent[0], a.cell), centres(a.extent[1], a.cell)
    z = a.height - np.tan(math.radians(a.slope)) * x[None, :] + 0.0 * y[:, None]
    write_asc(a.out, z, 0.0, 0.0, a.cell)
else:
    rows = list(csv.DictReader(open(a.section)))
    lines = []
    for name in a.line.split(","):
        pts = sorted((float(r["x"]), float(r["z"])) for r in rows if r["line"] == name)
        if not pts:
            raise SystemExit(f"make_rasters.py: {a.section} has no line '{name}'")
        lines.append(np.array(pts).T)
    lo = min(l[0].min() for l in lines)
    hi = max(l[0].max() for l in lines)
    x = centres(hi - lo, a.cell) + lo
    zx = np.full(len(x), np.nan)
    for k, (lx, lz) in enumerate(lines):  # the first line that reaches x gives its elevation
        take = np.isnan(zx) & (x >= lx.min()) & (x <= lx.max())
        if k == 0:  # the first line also holds over the part cell past its end
            take |= np.isnan(zx) & (x > lx.max()) & (x < lx.max() + a.cell)
        zx[take] = np.interp(x[take], lx, lz)
    y = centres(a.width, a.cell)
    # The flanks: the distance into the flank band from its inner edge, times the slope.
    into = np.maximum(0.0, np.maximum(a.flank_width - y, y - (a.width - a.flank_width)))
    rise = np.tan(math.radians(a.flank)) * into if a.flank > 0 else 0.0 * y
    write_asc(a.out, zx[None, :] + rise[:, None], lo, 0.0, a.cell)
