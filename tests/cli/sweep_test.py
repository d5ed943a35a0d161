#!/usr/bin/env python3
"""talus sweep end to end.

2D, a back-analysis against a closed form: the sliding block (1 m square on a 30 degree plane)
swept over the contact friction on a grid, scored against the centroid's horizontal
displacement a rigid block makes at t = 2 s with mu = 0.1,
dx = cos 30 g t^2 (sin 30 - mu cos 30) / 2; the ranking must put mu = 0.1 first, every run must be
within 1 % of its own closed form, and the probability profile must hold shares of the runs.

3D, the volcano slide (a real DEM) by Latin hypercube over two parameters:
- a sweep stopped with SIGTERM, and another killed with SIGKILL, in the middle of a run, then
  resumed, give the table of an uninterrupted sweep, byte for byte (runs continue from their
  checkpoints; done runs are not redone);
- the probability map of reaching is the mean of the runs' reached cells, on the DEM's grid;
- each run's critical success index against the observed outline is the one this test computes
  itself (cell centres in the outline's polygons by matplotlib's point-in-polygon);
- a folder holding another sweep, or files talus did not write, is refused; a [sweep] key the
  case does not have fails before any run, naming the line.

Usage: sweep_test.py TALUS SOURCE_DIR WORK_DIR
"""
import json
import math
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import rasterio
from matplotlib.path import Path as Polygon

talus, source, work = sys.argv[1], Path(sys.argv[2]).resolve(), Path(sys.argv[3])
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)
failures = []


def sweep(case, out, *extra, check=True):
    p = subprocess.run([talus, "sweep", str(case), "--out", str(out), *extra],
                       capture_output=True, text=True, timeout=900)
    if check and p.returncode != 0:
        sys.exit(f"sweep {out.name} failed ({p.returncode}): {p.stderr[-2000:]}")
    return p


def table(folder):
    return (folder / "table.csv").read_text()


def rows(path):
    lines = path.read_text().splitlines()
    head = lines[0].split(",")
    return [dict(zip(head, line.split(","))) for line in lines[1:]]


# ------------------------------------------------------------------------------------------
# 2D: friction recovered from the closed form's displacement.
g, t_end, mu_true = 9.81, 2.0, 0.1
c30, s30 = math.cos(math.radians(30)), math.sin(math.radians(30))


def closed_dx(mu):
    return c30 * g * t_end ** 2 * (s30 - mu * c30) / 2


block = work / "block_sweep.toml"
block.write_text((source / "cases/benchmarks/sliding_block.toml").read_text() + f"""
[results]
body = "block"

[maps]
bodies = ["block"]
cell_size = 0.5

[sweep]
design = "grid"
exceed = {{ peak_speed = [5.0] }}

[[sweep.parameter]]
key = "contact.0.friction"
values = [0.0, 0.05, 0.1, 0.15, 0.2]

[observed]
figures = {{ centroid_displacement_x_m = {closed_dx(mu_true):.6f} }}
""")
out2 = work / "block"
sweep(block, out2, "--jobs", "2")
ranked = rows(out2 / "ranking.csv")
if ranked[0]["contact.0.friction"] != "0.1":
    failures.append(f"2D: ranked first {ranked[0]['contact.0.friction']}, not 0.1: "
                    f"{[(r['contact.0.friction'], r['figures_rms_miss']) for r in ranked]}")
for r in ranked:
    mu, dx = float(r["contact.0.friction"]), float(r["centroid_displacement_x_m"])
    if abs(dx / closed_dx(mu) - 1) > 0.01:
        failures.append(f"2D: mu {mu}: centroid dx {dx:.4f} m against the closed form "
                        f"{closed_dx(mu):.4f} m")
    miss = abs(float(r["figures_rms_miss"]))
    if abs(miss - abs(dx / closed_dx(mu_true) - 1)) > 1e-6:
        failures.append(f"2D: mu {mu}: miss {miss}, not |dx / observed - 1|")
profile = np.genfromtxt(out2 / "maps/probability_profile.csv", delimiter=",", names=True,
                        skip_header=1)
share = profile["reached"]
if share.max() != 1.0 or not set(np.round(share * 5, 9)) <= set(range(6)):
    failures.append(f"2D: the reached shares are not fifths up to 1: {sorted(set(share))}")
if not (profile["peak_speed_above_5"] <= share).all():
    failures.append("2D: more runs above 5 m/s than reached a cell")

# ------------------------------------------------------------------------------------------
# 3D: the volcano by Latin hypercube, stopped and resumed.
volcano = (source / "cases/examples/volcano_slide.toml").read_text()
volcano = volcano.replace('"volcano/', f'"{source}/cases/examples/volcano/')
volcano = volcano[:volcano.index("[sweep]")] + """[sweep]
design = "lhs"
runs = 4
seed = 7
exceed = { peak_thickness = [2.0] }

[[sweep.parameter]]
key = "interface.0.friction.residual"
range = [0.26, 0.34]

[[sweep.parameter]]
key = "material.scoria_soil.friction_angle"
distribution = "normal"
mean = 33.0
sd = 2.0
range = [29.0, 37.0]
""" + volcano[volcano.index("[observed]"):]
case3 = work / "volcano_sweep.toml"
case3.write_text(volcano)
short = ["--set", "simulation.end_time=3.0", "--set", "output.particles=false",
         "--set", "checkpoint.wall_minutes=0"]
whole = work / "whole"
sweep(case3, whole, "--jobs", "2", *short)
reference = table(whole)


def stopped_then_resumed(name, sig):
    folder = work / name
    p = subprocess.Popen([talus, "sweep", str(case3), "--out", str(folder), "--jobs", "1", *short],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 300
    # Stop it once the first run is done and the second has stepped a tenth of its time (its log's
    # progress line: a run takes about a second, so a fixed wait could outlast it).
    log = folder / "logs" / "run_001.log"
    while time.time() < deadline:
        progress = re.findall(r"^t = \S+ / \S+ s +([0-9.]+) %", log.read_text(), re.M) \
            if log.exists() else []
        if any(10 <= float(share) < 100 for share in progress):
            break
        time.sleep(0.01)
    p.send_signal(sig)
    p.communicate(timeout=120)
    if sig == signal.SIGTERM and p.returncode != 128 + signal.SIGTERM:
        failures.append(f"{name}: the stopped sweep exited {p.returncode}, not 143")
    first = json.loads((folder / "run_000/summary.json").read_text())["wall_seconds"]
    resumed = sweep(case3, folder, "--jobs", "1", *short)
    if "(1 done)" not in resumed.stdout:
        failures.append(f"{name}: the resumed sweep did not find one run done: "
                        f"{resumed.stdout[:300]}")
    if json.loads((folder / "run_000/summary.json").read_text())["wall_seconds"] != first:
        failures.append(f"{name}: the done run was run again")
    if table(folder) != reference:
        failures.append(f"{name}: the resumed table differs from the uninterrupted one:\n"
                        f"{table(folder)}\n{reference}")


stopped_then_resumed("sigterm", signal.SIGTERM)
stopped_then_resumed("sigkill", signal.SIGKILL)

# The probability of reaching: the mean of the runs' reached cells, on the DEM's grid.
dem = rasterio.open(source / "cases/examples/volcano/maunga_whau.asc")
reached = []
for run in sorted(whole.glob("run_*")):
    with rasterio.open(run / "maps/peak_thickness.tif") as r:
        reached.append(r.read(1, masked=True).filled(0) > 0)
with rasterio.open(whole / "maps/probability_reached.tif") as r:
    prob = r.read(1, masked=True)
    if r.transform != dem.transform or (r.width, r.height) != (dem.width, dem.height):
        failures.append(f"probability map on {r.width} x {r.height} {r.transform}, not the DEM's")
if not np.array_equal(prob.filled(0), np.mean(reached, axis=0).astype(np.float32)):
    failures.append("probability_reached.tif is not the mean of the runs' reached cells")
if not (whole / "plots/map_probability_reached.png").exists():
    failures.append("no picture of the probability map")

# The critical success index, computed here from the outline's polygons.
outline = json.loads((source / "cases/examples/volcano/twin_impact_area.geojson").read_text())
rings = [Polygon(f["geometry"]["coordinates"][0]) for f in outline["features"]]
cols, rws = np.meshgrid(np.arange(dem.width), np.arange(dem.height))
xs, ys = dem.transform * (cols + 0.5, rws + 0.5)
centres = np.column_stack([xs.ravel(), ys.ravel()])
observed = np.zeros(centres.shape[0], bool)
for ring in rings:
    observed |= ring.contains_points(centres)
observed = observed.reshape(dem.height, dem.width)
for k, r in enumerate(rows(whole / "table.csv")):
    sim = reached[k]
    tp, fp, fn = (sim & observed).sum(), (sim & ~observed).sum(), (~sim & observed).sum()
    csi = tp / (tp + fp + fn)
    if abs(float(r["csi"]) - csi) > 1e-5:
        failures.append(f"{r['run']}: CSI {r['csi']} against {csi:.6f} computed here")
    if abs(float(r["observed_area_reached"]) - tp / (tp + fn)) > 1e-5:
        failures.append(f"{r['run']}: share of the observed area {r['observed_area_reached']}")

# Refusals: another design in the folder, a folder with someone else's files, a wrong key.
p = sweep(case3, whole, *short, "--set", "sweep.seed=8", check=False)
if p.returncode != 2 or "holds another sweep" not in p.stderr:
    failures.append(f"another design in the folder: {p.returncode} {p.stderr}")
foreign = work / "foreign"
foreign.mkdir()
(foreign / "notes.txt").write_text("mine")
p = sweep(case3, foreign, *short, check=False)
if p.returncode != 2 or "did not write" not in p.stderr or \
        (foreign / "notes.txt").read_text() != "mine":
    failures.append(f"a folder with a foreign file: {p.returncode} {p.stderr}")
bad = work / "bad_key.toml"
bad.write_text(volcano.replace('key = "interface.0.friction.residual"',
                               'key = "interface.0.fricton.residual"'))
p = sweep(bad, work / "bad", check=False)
line = volcano[:volcano.index('key = "interface.0.friction.residual"')].count("\n") + 1
if p.returncode != 2 or f"bad_key.toml:{line}: sweep.parameter[0].key" not in p.stderr or \
        (work / "bad").exists():
    failures.append(f"a key the case does not have: {p.returncode} {p.stderr}")

for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
