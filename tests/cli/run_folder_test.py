#!/usr/bin/python3
"""The run-folder contract, end to end: run the example case with the real program, then read
its ParaView output with meshio and with VTK's own reader, and check it against the CSVs and
summary."""
import csv
import json
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

import meshio
import numpy as np

talus, source, out = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(out, ignore_errors=True)
case = os.path.join(source, "cases/examples/block_on_floor.toml")
subprocess.run([talus, "run", case, "--out", out, "--set", "simulation.end_time=0.2",
                "--set", "output.every=0.1"], check=True, stdout=subprocess.DEVNULL)

summary = json.load(open(os.path.join(out, "summary.json")))
for key in ["talus_version", "case", "dimension", "particles", "bodies", "steps", "simulated_time",
            "wall_seconds", "particle_updates_per_second", "threads", "status", "results"]:
    assert key in summary, key
assert summary["status"] == "completed"
assert abs(summary["simulated_time"] - 0.2) < 1e-12
assert "'simulation.end_time=0.2'" in open(os.path.join(out, "case.toml")).read()

frames = ET.parse(os.path.join(out, "particles.pvd")).getroot().findall(".//DataSet")
assert [float(f.get("timestep")) for f in frames] == [0.0, 0.1, 0.2], frames
assert not [f for f in os.listdir(out) if f.endswith(".tmp")]

last = meshio.read(os.path.join(out, frames[-1].get("file")))
# Positions are float32 (output.position_precision "auto"): rounded by at most a 2,000th of a cell.
cell = float(re.search(r"cell_size = ([0-9.eE+-]+)", open(case).read()).group(1))
assert last.points.dtype == np.float32, last.points.dtype
rounding = cell / 2000
n = summary["particles"]
assert last.points.shape == (n, 3), last.points.shape
for field in ["body", "id", "velocity", "displacement", "stress", "mass", "volume", "plastic_strain"]:
    assert field in last.point_data, field
    assert np.all(np.isfinite(last.point_data[field])), field
body = last.point_data["body"].ravel()
for b, (name, info) in enumerate(summary["bodies"].items()):
    assert np.count_nonzero(body == b) == info["particles"], name

# The VTU agrees with bodies.csv: mass and centroid of each body at the last frame.
rows = [r for r in csv.DictReader(open(os.path.join(out, "bodies.csv"))) if float(r["time"]) == 0.2]
mass = last.point_data["mass"].ravel()
for b, row in enumerate(rows):
    m = mass[body == b]
    centroid = (m[:, None] * last.points[body == b, :2]).sum(axis=0) / m.sum()
    assert abs(m.sum() - float(row["mass"])) < 1e-9 * m.sum(), row
    assert np.allclose(centroid, [float(row["centroid_x"]), float(row["centroid_y"])], rtol=1e-9,
                       atol=rounding), (centroid, row)

# Displacement is position minus initial position.
first = meshio.read(os.path.join(out, frames[0].get("file")))
order0 = np.argsort(first.point_data["id"].ravel())
order1 = np.argsort(last.point_data["id"].ravel())
disp = last.points[order1] - first.points[order0]
assert np.allclose(disp, last.point_data["displacement"][order1], atol=2 * rounding)
# The nodal contact forces (output.contact_nodes): a series beside the particles'. The sliding
# block rests on its plane, so the forces on it hold about the weight's normal part.
cout = out + "_contact"
shutil.rmtree(cout, ignore_errors=True)
subprocess.run([talus, "run", os.path.join(source, "cases/benchmarks/sliding_block.toml"), "--out",
                cout, "--set", "simulation.end_time=0.1", "--set", "output.every=0.05", "--set",
                "output.contact_nodes=true"], check=True, stdout=subprocess.DEVNULL)
cframes = ET.parse(os.path.join(cout, "contact_nodes.pvd")).getroot().findall(".//DataSet")
assert [float(f.get("timestep")) for f in cframes] == [0.0, 0.05, 0.1], cframes
nodes = meshio.read(os.path.join(cout, cframes[-1].get("file")))
for field in ["body", "other", "force", "normal", "frictional_force", "cohesive_force"]:
    assert field in nodes.point_data, field
on_block = nodes.point_data["body"].ravel() == 0
assert on_block.sum() > 3, on_block.sum()
normal = -(nodes.point_data["force"] * nodes.point_data["normal"]).sum(axis=1)[on_block].sum()
mass = float(next(csv.DictReader(open(os.path.join(cout, "bodies.csv"))))["mass"])
assert 0.7 < normal / (mass * 9.81 * np.cos(np.pi / 6)) < 1.3, normal

# VTK's own reader (python3-vtk9) reads the compressed appended frames: the same points and
# fields as meshio, fields and positions in float32 by default (positions: "auto" on this small grid).
import vtk
from vtk.util.numpy_support import vtk_to_numpy
for folder, frame in [(out, frames[-1]), (cout, cframes[-1])]:
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(os.path.join(folder, frame.get("file")))
    reader.Update()
    grid = reader.GetOutput()
    mesh = meshio.read(os.path.join(folder, frame.get("file")))
    assert grid.GetNumberOfPoints() == len(mesh.points) > 0, grid.GetNumberOfPoints()
    assert np.array_equal(vtk_to_numpy(grid.GetPoints().GetData()), mesh.points)
    pd = grid.GetPointData()
    for name, values in mesh.point_data.items():
        assert np.array_equal(vtk_to_numpy(pd.GetArray(name)).reshape(values.shape), values), name
velocity = vtk.vtkXMLUnstructuredGridReader()
velocity.SetFileName(os.path.join(out, frames[-1].get("file")))
velocity.Update()
assert velocity.GetOutput().GetPointData().GetArray("velocity").GetDataTypeAsString() == "float"
assert velocity.GetOutput().GetPoints().GetData().GetDataTypeAsString() == "float"  # "auto"

# legend.json names the values of `body` and `material` (ParaView colour-map presets).
import tomllib
legend = json.load(open(os.path.join(out, "legend.json")))
as_run = tomllib.load(open(os.path.join(out, "case_as_run.toml"), "rb"))
assert as_run["simulation"]["end_time"] == 0.2 and "run" not in as_run
names = [b["name"] for b in as_run["body"]]
assert legend[0]["Annotations"] == [x for i, n in enumerate(names) for x in (str(i), n)], legend[0]
assert len(legend[0]["IndexedColors"]) == 3 * len(names)
assert legend[1]["Annotations"][1::2] == [m["name"] for m in as_run["material"]], legend[1]

# The plot tool: a misspelt field lists the ones it can plot (exit 2); the body snapshot has a
# legend of the bodies' names and axis labels (it is written).
plot = os.path.join(source, "tools/plot_run.py")
p = subprocess.run(["/usr/bin/python3", plot, out, "--field", "stres_yy"], capture_output=True,
                   text=True)
assert p.returncode == 2 and "stress_yy" in p.stderr and "Traceback" not in p.stderr, p.stderr
p = subprocess.run(["/usr/bin/python3", plot, out, "--field", "body", "--frames", "1"],
                   capture_output=True, text=True)
assert p.returncode == 0 and os.path.exists(os.path.join(out, "plots", "snapshot_body_0002.png")), p.stderr

print(f"run folder ok: {n} particles, {len(frames)} frames read by meshio {meshio.__version__}")
