#!/usr/bin/env python3
"""The tutorial "your slope from a DEM" (docs/hazard-maps.md) runs as written: its bash blocks,
in order, from the source folder, with HOME in the work folder (the tutorial works in
~/my_slope) and this build's talus in place of build/release's. Then what the tutorial says it
made is there: the maps in the DEM's coordinate system (EPSG:2193, the corner it placed), the
figures it quotes (within a cell's worth), the pictures, and the sweep's table and probability
maps.

Usage: tutorial_test.py TALUS SOURCE_DIR WORK_DIR
"""
import json
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import rasterio

talus, source, work = Path(sys.argv[1]).resolve(), Path(sys.argv[2]).resolve(), Path(sys.argv[3])
work = work.resolve()
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)
doc = (source / "docs/hazard-maps.md").read_text()
blocks = re.findall(r"```bash\n(.*?)```", doc, re.S)
script = "\n".join(blocks)
export = 'export PATH="$T/build/release:$PATH"'
if export not in script:
    sys.exit(f"the tutorial no longer has the line {export!r} this test replaces")
script = script.replace(export, f'export PATH="{talus.parent}:$PATH"')
env = dict(os.environ, HOME=str(work), PATH="/usr/bin:/bin:" + os.environ.get("PATH", ""))
t0 = time.time()
p = subprocess.run(["bash", "-euo", "pipefail", "-c", script], cwd=source, env=env,
                   capture_output=True, text=True, timeout=1200)
print(f"the tutorial ran in {time.time() - t0:.0f} s")
if p.returncode != 0:
    sys.exit(f"the tutorial failed ({p.returncode}):\n{p.stdout[-2000:]}\n{p.stderr[-3000:]}")

failures = []
slope = work / "my_slope"
with rasterio.open(slope / "runs/slope/maps/peak_thickness.tif") as r:
    if r.crs is None or r.crs.to_epsg() != 2193:
        failures.append(f"maps in {r.crs}, not EPSG:2193")
    if (r.transform.c, r.transform.f, r.transform.a) != (1756000.0, 5916370.0, 10.0):
        failures.append(f"maps' transform {r.transform}, not the DEM's")
maps = json.loads((slope / "runs/slope/summary.json").read_text())["results"]["maps"]
quoted = {"impact_area_m2": (19900, 300), "runout_length_m": (166, 10), "drop_height_m": (77, 5),
          "fahrboschung_angle_deg": (24.8, 1.0), "peak_speed_m_s": (17.5, 0.5)}
for key, (value, within) in quoted.items():
    if abs(maps[key] - value) > within:
        failures.append(f"{key} {maps[key]:.4g}, the tutorial says {value}")
for f in ("plots/map_peak_thickness.png", "plots/map_intensity.png"):
    if not (slope / "runs/slope" / f).exists():
        failures.append(f"no {f}")
sweep = slope / "runs/slope_sweep"
rows = (sweep / "table.csv").read_text().splitlines()
if len(rows) != 4 or any(",completed," not in r for r in rows[1:]):
    failures.append(f"the sweep's table: {rows}")
for f in ("maps/probability_reached.tif", "maps/probability_peak_thickness_above_2.tif",
          "maps/probability_peak_pressure_above_10000.tif", "plots/map_probability_reached.png"):
    if not (sweep / f).exists():
        failures.append(f"no {f} in the sweep")
for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
