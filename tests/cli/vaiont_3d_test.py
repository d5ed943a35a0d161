#!/usr/bin/env python3
"""The 3D Vaiont built from rasters (cases/vaiont/rigid_boundary_3d.toml) against its 2D section
(cases/vaiont/rigid_boundary.toml) at the same 16 m spacing. The 3D case is the section extruded
across a 1,696 m valley between smooth walls, so it is a plane-strain problem: its slide must
move as the 2D one does, and the same in every slice across the valley. Through the release and
the peak (20 s after 10 s of settling):
- the slide's peak mean speed within 2 % of the 2D case's, its centroid's displacement along x
  within 3 % (docs/vaiont.md, "The Vaiont in 3D", measured over the whole run: 0.7 and 2.8 %);
- the slices at the valley's two walls (the outer two particle rows, 32 m, on each side) moved
  as the middle slice: their mean x displacement within 2 % of the middle's, their mean
  elevation within 2 m. A normal that is wrong at the terrain's edge on the grid's face let
  the slide fall through the boundary there once;
- no slide particle lies below the rigid boundary's top (the failure surface, then the valley
  floor and the north slope) by more than a cell.

Usage: vaiont_3d_test.py TALUS SOURCE_DIR WORK_DIR
"""
import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

talus, source, work = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)
end = 20.0
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def run(case, name, *settings):
    out = work / name
    p = subprocess.run([talus, "run", str(source / "cases/vaiont" / case), "--out", str(out),
                        "--set", f"simulation.end_time={end}", "--set", f"output.every={end}",
                        *[a for s in settings for a in ("--set", s)], "--threads", "2"],
                       capture_output=True, text=True, timeout=900)
    if p.returncode != 0:
        sys.exit(f"{case} failed ({p.returncode}): {p.stderr[-1500:]}")
    summary = json.loads((out / "summary.json").read_text())
    return out, summary["results"]


# The 2D section at the 3D case's spacing and degradation slip (1 % of 16 m).
_, two = run("rigid_boundary.toml", "2d", "grid.cell_size=32",
             "interface.0.friction.slip=0.16", "interface.0.cohesion.slip=0.16")
out, three = run("rigid_boundary_3d.toml", "3d", 'output.fields=["displacement"]')

speed2, speed3 = two["peak_mean_speed_m_s"], three["peak_mean_speed_m_s"]
dx2, dx3 = two["centroid_displacement_x_m"], three["centroid_displacement_x_m"]
print(f"peak mean speed: 3D {speed3:.2f} m/s, 2D {speed2:.2f} ({100 * (speed3 / speed2 - 1):+.2f} %)")
print(f"centroid dx at {end:g} s: 3D {dx3:.1f} m, 2D {dx2:.1f} ({100 * (dx3 / dx2 - 1):+.2f} %)")
check(speed2 > 15.0, f"the 2D slide runs (peak mean speed {speed2:.1f} m/s)")
check(abs(speed3 / speed2 - 1) < 0.02, "the 3D slide's peak mean speed within 2 % of the 2D one's")
check(abs(dx3 / dx2 - 1) < 0.03, "the 3D slide's centroid displacement within 3 % of the 2D one's")

# The last frame's slide particles (the rigid boundary, fixed, is in particles_fixed.vtu).
reader = vtk.vtkXMLUnstructuredGridReader()
reader.SetFileName(str(out / "particles_000001.vtu"))
reader.Update()
grid = reader.GetOutput()
x = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
body = vtk_to_numpy(grid.GetPointData().GetArray("body"))
disp = vtk_to_numpy(grid.GetPointData().GetArray("displacement")).astype(float)
slide = body == 0
x, disp = x[slide], disp[slide]
y0 = x[:, 1] - disp[:, 1]  # each particle's slice across the valley, where it started
width, rows = 1696.0, 32.0
middle = np.abs(y0 - width / 2) < rows
for name, near in (("y = 0", y0 < rows), ("y = 1,696 m", y0 > width - rows)):
    share = disp[near, 0].mean() / disp[middle, 0].mean() - 1
    dz = x[near, 2].mean() - x[middle, 2].mean()
    print(f"slice at {name}: {near.sum()} particles, mean dx {100 * share:+.2f} % of the middle's, "
          f"mean elevation {dz:+.2f} m from the middle's")
    check(near.sum() > 0 and abs(share) < 0.02 and abs(dz) < 2.0,
          f"the slice at the wall {name} moved as the middle slice")

# The boundary's top below each particle (the raster's 8 m cell that holds it; row 0 is the
# northernmost, y from yllcorner + nrows cells down), against its z.
raster = (source / "cases/vaiont/3d/boundary_top.asc").read_text().split("\n")
head = {}
k = 0
while raster[k].split()[0].lower() in ("ncols", "nrows", "xllcorner", "yllcorner", "cellsize",
                                       "nodata_value", "xllcenter", "yllcenter"):
    key, value = raster[k].split()[:2]
    head[key.lower()] = float(value)
    k += 1
z = np.array([[float(v) for v in line.split()] for line in raster[k:] if line.strip()])
cell = head["cellsize"]
x0 = head.get("xllcorner", head.get("xllcenter", 0.0) - cell / 2)
y0r = head.get("yllcorner", head.get("yllcenter", 0.0) - cell / 2)
col = np.clip(np.floor((x[:, 0] - x0) / cell).astype(int), 0, z.shape[1] - 1)
row = np.clip(np.floor(z.shape[0] - (x[:, 1] - y0r) / cell).astype(int), 0, z.shape[0] - 1)
below = z[row, col] - x[:, 2]
print(f"deepest slide particle below the boundary's top: {below.max():.1f} m (cells 32 m)")
check(below.max() < 32.0, "no slide particle below the rigid boundary's top by more than a cell")

if failures:
    sys.exit("FAILED: " + "; ".join(failures))
print("3D Vaiont against its 2D section: ok")
