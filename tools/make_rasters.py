#!/usr/bin/env python3
"""Writes the elevation rasters (ESRI ASCII grids, which GDAL reads, or GeoTIFF where a name ends
in .tif) that Talus's terrain cases ship:

  plane OUT.asc --slope DEG --extent X Y --cell H --height Z0
      the plane z = Z0 - x tan(slope) over [0, X] x [0, Y] (cases/benchmarks/terrain_block.toml)

  section SECTION.csv LINE[,LINE...] OUT --width W --cell H [--y0 Y0] [--flank DEG --flank-width B]
      a 2D section's line z(x) (section.csv's `line,x,z` rows, e.g. ground_before or
      failure_surface; with several, each x takes the first line that reaches it) extruded
      across the valley along y over [Y0, Y0 + W] (Y0 = 0 by default); with --flank, the surface
      rises at DEG degrees over the last B metres on either side (a valley whose flanks close the
      slide in) (cases/vaiont/3d/)

  bowl DEM OUT --centre X Y --axes A B --depth D [--footprint OUT.csv]
      a failure surface under a ground raster (ESRI ASCII, GeoTIFF or anything GDAL reads): the
      ground lowered by the half-ellipsoid D (1 - ((x - X)/A)^2 - ((y - Y)/B)^2) inside the
      ellipse and equal to it outside, on the ground's own cells and in its coordinate system
      (cases/examples/volcano/); --footprint writes the ellipse as a 48-gon CSV (x,y) for the
      slide's footprint

  georeference IN.asc OUT.tif --epsg CODE --corner E N
      a local grid placed in a projected coordinate system: its south-west corner at (E, N), the
      system's EPSG code in the GeoTIFF (docs/hazard-maps.md makes its DEM so)

Each cell holds the surface at its centre; the grid's south-west corner is the origin (plane;
section at y = Y0; bowl keeps the DEM's). section, bowl and georeference write a GeoTIFF
(DEFLATE) where OUT ends in .tif, plane always ESRI ASCII.
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


def read_raster(path):
    """Any raster GDAL reads: (z[j, i] with j along y from the south, x0, y0, cell, profile)."""
    if str(path).lower().endswith(".asc"):
        return (*read_asc(path), None)
    import rasterio
    with rasterio.open(path) as r:
        t = r.transform
        if t.b != 0 or t.d != 0 or abs(t.a) != abs(t.e):
            raise SystemExit(f"make_rasters.py: {path}: a rotated or non-square grid")
        z = r.read(1).astype(float)[::-1]
        return z, t.c, t.f + t.e * r.height, t.a, r.profile


def write_raster(path, z, x0, y0, cell, profile=None, epsg=None):
    """ESRI ASCII, or GeoTIFF (DEFLATE, north up, no data -9999) where the name ends in .tif."""
    if not str(path).lower().endswith(".tif"):
        return write_asc(path, z, x0, y0, cell)
    import rasterio
    from rasterio.transform import from_origin
    ny, nx = z.shape
    crs = rasterio.crs.CRS.from_epsg(epsg) if epsg else (profile or {}).get("crs")
    with rasterio.open(path, "w", driver="GTiff", width=nx, height=ny, count=1,
                       dtype="float32", crs=crs, nodata=-9999.0, compress="deflate",
                       transform=from_origin(x0, y0 + ny * cell, cell, cell)) as w:
        w.write(z[::-1].astype("float32"), 1)


def read_asc(path):
    """An ESRI ASCII grid: (z[j, i] with j along y from the south, x0, y0, cell)."""
    head = {}
    with open(path) as f:
        for _ in range(6):
            k, v = f.readline().split()
            head[k.lower()] = float(v)
        z = np.loadtxt(f)[::-1]
    if "xllcorner" not in head or z.shape != (int(head["nrows"]), int(head["ncols"])):
        raise SystemExit(f"make_rasters.py: {path} is not an ESRI ASCII grid with corner origin")
    return z, head["xllcorner"], head["yllcorner"], head["cellsize"]


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
s.add_argument("--y0", type=float, default=0.0, help="the raster's southern edge (m)")
s.add_argument("--flank", type=float, default=0.0, help="flank slope (degrees), 0: none")
s.add_argument("--flank-width", type=float, default=0.0)
b = sub.add_parser("bowl")
b.add_argument("dem")
b.add_argument("out")
b.add_argument("--centre", type=float, nargs=2, required=True)
b.add_argument("--axes", type=float, nargs=2, required=True)
b.add_argument("--depth", type=float, required=True)
b.add_argument("--footprint")
g = sub.add_parser("georeference")
g.add_argument("src")
g.add_argument("out")
g.add_argument("--epsg", type=int, required=True)
g.add_argument("--corner", type=float, nargs=2, required=True)
a = ap.parse_args()

if a.kind == "plane":
    x, y = centres(a.extent[0], a.cell), centres(a.extent[1], a.cell)
    z = a.height - np.tan(math.radians(a.slope)) * x[None, :] + 0.0 * y[:, None]
    write_asc(a.out, z, 0.0, 0.0, a.cell)
elif a.kind == "georeference":
    z, _, _, cell, _ = read_raster(a.src)
    write_raster(a.out, z, a.corner[0], a.corner[1], cell, epsg=a.epsg)
elif a.kind == "bowl":
    z, x0, y0, cell, profile = read_raster(a.dem)
    ny, nx = z.shape
    x, y = x0 + (np.arange(nx) + 0.5) * cell, y0 + (np.arange(ny) + 0.5) * cell
    r2 = ((x[None, :] - a.centre[0]) / a.axes[0]) ** 2 + ((y[:, None] - a.centre[1]) / a.axes[1]) ** 2
    write_raster(a.out, z - a.depth * np.maximum(0.0, 1.0 - r2), x0, y0, cell, profile)
    if a.footprint:
        with open(a.footprint, "w") as f:
            f.write("x,y\n")
            for k in range(48):
                t = 2.0 * math.pi * k / 48
                f.write(f"{a.centre[0] + a.axes[0] * math.cos(t):.3f},"
                        f"{a.centre[1] + a.axes[1] * math.sin(t):.3f}\n")
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
    write_raster(a.out, zx[None, :] + rise[:, None], lo, a.y0, a.cell)
