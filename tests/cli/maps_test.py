#!/usr/bin/env python3
"""Hazard maps end to end: the volcano slide (a real DEM) run with its [maps] table writes its
GeoTIFFs on the DEM's grid, which rasterio (GDAL underneath, as QGIS) reads with the DEM's
georeferencing, units and no data; the fields are consistent with each other (a cell has a speed
and an arrival time where, and only where, moving material passed; the pressure is rho u^2 with
rho between the slide's density and its loosened state; the release area lies inside the
reached cells); the outlines (GeoJSON) enclose exactly the cells reached, deposited and
released; and tools/plot_maps.py draws every field; a 2D run writes its profile along the section (maps/profile.csv), which
plot_maps.py draws.

Usage: maps_test.py TALUS SOURCE_DIR WORK_DIR
"""
import json
import math
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import rasterio

talus, source, work = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)
run = work / "volcano"
p = subprocess.run([talus, "run", str(source / "cases/examples/volcano_slide.toml"), "--out",
                    str(run), "--set", "simulation.end_time=6.0", "--set",
                    "output.particles=false", "--threads", "2"], capture_output=True, text=True,
                   timeout=600)
if p.returncode != 0:
    sys.exit(f"the volcano run failed ({p.returncode}): {p.stderr[-1500:]}")
failures = []


def read(stem):
    """The band and what the file says of it (read while open)."""
    with rasterio.open(run / "maps" / f"{stem}.tif") as r:
        return r.read(1, masked=True), dict(width=r.width, height=r.height,
                                            transform=r.transform, units=r.units,
                                            nodata=r.nodata, names=r.descriptions,
                                            tags=r.tags())


dem = rasterio.open(source / "cases/examples/volcano/maunga_whau.asc")
fields = {}
for stem, unit in [("peak_thickness", "m"), ("peak_speed", "m/s"),
                   ("peak_kinetic_energy", "J/m^2"), ("peak_pressure", "Pa"),
                   ("arrival_time", "s"), ("deposit_thickness", "m"),
                   ("release_thickness", "m"), ("elevation", "m")]:
    data, r = read(stem)
    fields[stem] = data
    if (r["width"], r["height"]) != (dem.width, dem.height) or r["transform"] != dem.transform:
        failures.append(f"{stem}: grid {r['width']} x {r['height']} {r['transform']}, not the "
                        "DEM's")
    if r["units"][0] != unit or r["nodata"] != -9999.0 or r["names"][0] != stem:
        failures.append(f"{stem}: unit {r['units']}, no data {r['nodata']}, name {r['names']}")
    if r["tags"].get("TALUS_BODIES") != "slide":
        failures.append(f"{stem}: metadata {r['tags']}")
h, u, e, pr, t = (fields[k] for k in ("peak_thickness", "peak_speed", "peak_kinetic_energy",
                                      "peak_pressure", "arrival_time"))
reached = h.filled(0) > 0
if reached.sum() < 50:
    failures.append(f"only {reached.sum()} cells reached")
if not np.array_equal(reached, ~t.mask) or not np.array_equal(reached, u.filled(0) > 0):
    failures.append("thickness, speed and arrival time disagree on the cells reached")
if t.max() > 6.0 + 1e-6 or t.min() < 0:
    failures.append(f"arrival times {t.min()} to {t.max()} s outside the run")
rho = pr[reached] / u[reached] ** 2
if rho.min() < 300 or rho.max() > 1900 * 1.001:
    failures.append(f"rho u^2 / u^2 from {rho.min():.0f} to {rho.max():.0f} kg/m^3, not a "
                    "density up to the slide's 1900")
# The ground under the maps is the DEM's, sampled at the cells' centres.
z = fields["elevation"]
if abs(float(z[40, 30]) - float(dem.read(1)[40, 30])) > 1e-3:
    failures.append(f"elevation.tif {z[40, 30]} against the DEM's {dem.read(1)[40, 30]}")
# The intensity classes (Swiss debris-flow defaults): 3 where h > 1 m and u > 1 m/s, else 2.
klass, r = read("intensity")
expected = np.where(reached, np.where((h.filled(0) > 1.0) & (u.filled(0) > 1.0), 3, 2), -1)
if r["units"][0] != "class" or not np.array_equal(klass.filled(-1), expected):
    failures.append(f"intensity.tif: unit {r['units']}, classes "
                    f"{np.unique(klass.filled(-1), return_counts=True)} against "
                    f"{np.unique(expected, return_counts=True)}")
if not (expected == 3).any() or not (expected == 2).any():
    failures.append("intensity: the volcano run should have both high and medium cells")
# The ground's change: the deposit less the release.
change, _ = read("thickness_change")
if not np.allclose(change.filled(0), fields["deposit_thickness"].filled(0) -
                   fields["release_thickness"].filled(0), atol=1e-4):
    failures.append("thickness_change.tif is not deposit_thickness - release_thickness")
released = fields["release_thickness"].filled(0) > 0
if released.sum() < 20 or np.any(released & ~reached):
    failures.append(f"release area {released.sum()} cells, {np.sum(released & ~reached)} outside "
                    "the reached cells")
# The outlines (GeoJSON polygons on the cells' edges): their areas are the cells' counts.


def ring_area(ring):
    return abs(sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(ring, ring[1:]))) / 2


for name, cells in [("impact_area", reached.sum()),
                    ("deposit_area", (fields["deposit_thickness"].filled(0) > 0).sum()),
                    ("release_area", released.sum())]:
    doc = json.loads((run / "maps" / f"{name}.geojson").read_text())
    area = sum(ring_area(f["geometry"]["coordinates"][0]) -
               sum(ring_area(h) for h in f["geometry"]["coordinates"][1:])
               for f in doc["features"])
    if abs(area - cells * 100.0) > 1e-6 or doc.get("name") != name:
        failures.append(f"{name}.geojson: {area} m^2 in {len(doc['features'])} polygons against "
                        f"{cells} cells of 100 m^2")
p = subprocess.run(["/usr/bin/python3", str(source / "tools/plot_maps.py"), str(run)],
                   capture_output=True, text=True, timeout=300)
pngs = sorted((run / "plots").glob("map_*.png"))
if p.returncode != 0 or len(pngs) != 8 or min(f.stat().st_size for f in pngs) < 20000:
    failures.append(f"plot_maps.py: exit {p.returncode}, {[f.name for f in pngs]}: {p.stderr}")
# 2D: the maps are the profile along the section (maps/profile.csv), drawn as profile.png.
section = work / "section"
p = subprocess.run([talus, "run", str(source / "cases/benchmarks/sliding_block.toml"), "--out",
                    str(section), "--set", 'maps.bodies=["block"]', "--set", "maps.cell_size=0.5",
                    "--set", "simulation.end_time=1.0", "--threads", "2"],
                   capture_output=True, text=True, timeout=600)
profile = section / "maps" / "profile.csv"
if p.returncode != 0 or not profile.exists():
    failures.append(f"2D maps: exit {p.returncode}: {p.stderr[-800:]}")
else:
    rows = np.genfromtxt(profile, delimiter=",", names=True, skip_header=1)
    if not (rows["peak_thickness"] > 0).any() or rows["peak_speed"].max() <= 0.1:
        failures.append(f"2D maps: nothing moved in {profile}")
    p = subprocess.run(["/usr/bin/python3", str(source / "tools/plot_maps.py"), str(section)],
                       capture_output=True, text=True, timeout=300)
    png = section / "plots" / "profile.png"
    if p.returncode != 0 or not png.exists() or png.stat().st_size < 20000:
        failures.append(f"plot_maps.py on a 2D run: exit {p.returncode}: {p.stderr}")

# A block down a raster plane (cases/benchmarks/terrain_block.toml: a 1 m square footprint,
# 0.57735 m high, on z = 2.6 - x tan 30): the release and deposit thickness integrate to its
# volume; the arrival time in each cell ahead of it is the closed form's, the time its front
# (the leading particles, a quarter cell behind the face at x = 1.4 m) needs to reach the cell's
# west edge, x(t) = a t^2 / 2 with a = g (sin 30 - mu cos 30) cos 30 in plan, within a cell's
# travel time; and a block that friction holds (mu 0.7 > tan 30) maps nothing moving and a
# deposit that is its release, up to the elastic block's volume change under its own weight
# (|dJ| <= rho g h / K = 2.7e-4 with K = E / (3 (1 - 2 nu)) = 41.7 MPa).
def block_maps(mu, end):
    folder = work / f"block_mu{mu}"
    p = subprocess.run([talus, "run", str(source / "cases/benchmarks/terrain_block.toml"),
                        "--out", str(folder), "--set", 'maps.bodies=["block"]', "--set",
                        "maps.cell_size=0.1", "--set", f"contact.0.friction={mu}", "--set",
                        f"simulation.end_time={end}", "--threads", "2"],
                       capture_output=True, text=True, timeout=600)
    if p.returncode != 0:
        sys.exit(f"terrain block, mu {mu}: exit {p.returncode}: {p.stderr[-800:]}")
    out = {}
    for stem in ("release_thickness", "deposit_thickness", "arrival_time", "peak_thickness",
                 "peak_speed"):
        with rasterio.open(folder / "maps" / f"{stem}.tif") as r:
            out[stem], transform = r.read(1, masked=True), r.transform
    return out, transform


volume, cell_area = 0.57735, 0.01
for mu in (0.0, 0.3):
    m, tr = block_maps(mu, 0.6)
    for stem in ("release_thickness", "deposit_thickness"):
        v = float(m[stem].filled(0).sum()) * cell_area
        if abs(v / volume - 1) > 0.01:
            failures.append(f"block, mu {mu}: {stem} integrates to {v:.5f} m^3, not {volume}")
    c30 = math.cos(math.radians(30))
    a = 9.81 * (0.5 - mu * c30) * c30
    checked = 0
    for i in range(15, m["arrival_time"].shape[1]):
        west = tr.c + i * tr.a
        expected = math.sqrt(2 * (west - (1.4 - 0.025)) / a)
        if expected > 0.6:
            break
        travel = tr.a / (a * expected)
        for j in range(4, 12):  # the rows under the block's footprint (y 0.3-1.3 m)
            got = float(m["arrival_time"][j, i])
            checked += 1
            if abs(got - expected) > travel:
                failures.append(f"block, mu {mu}: arrival at x {west:.1f} m (row {j}) "
                                f"{got:.4f} s against {expected:.4f} s (a cell: {travel:.4f} s)")
    if checked < 16:
        failures.append(f"block, mu {mu}: only {checked} arrival cells checked")
m, _ = block_maps(0.7, 0.3)
if m["peak_thickness"].filled(0).max() != 0 or m["peak_speed"].filled(0).max() != 0 or \
        (~m["arrival_time"].mask).any():
    failures.append("a block held by friction: something mapped as moving")
release = m["release_thickness"].filled(0)
change = np.abs(m["deposit_thickness"].filled(0) - release).max() / release.max()
if (release > 0).sum() < 90 or change > 2000 * 9.81 * 0.57735 / (50e6 / 1.2):
    failures.append(f"a block held by friction: its deposit is not its release ({change:.2e})")

for f in failures:
    print("FAIL", f)
print(f"maps: {reached.sum()} cells reached, peak {h.max():.1f} m, {u.max():.1f} m/s; "
      f"{len(pngs)} pictures")
sys.exit(1 if failures else 0)
