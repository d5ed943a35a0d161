#!/usr/bin/env python3
"""Faults that must end a run cleanly: a blow-up, a collapsing time step, an output folder that
cannot be created, and a full disk (a file-size limit, as `ulimit -f` sets). Each must give a
clear message and a non-zero exit, and leave every file already written intact and readable:
the last output frame, the CSVs, summary.json and the checkpoints.

Usage: failure_test.py TALUS SOURCE_DIR WORK_DIR
"""
import hashlib
import json
import os
import resource
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import meshio

talus, source, work = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
case = source / "cases/examples/block_on_floor.toml"
failures = []


def check(cond, msg):
    if not cond:
        failures.append(msg)


def run(args, file_limit=None, inject=None):
    env = dict(os.environ)
    env.pop("TALUS_INJECT_SIGNAL", None)
    if inject:
        env["TALUS_INJECT_SIGNAL"] = f"{int(inject[0])}:{inject[1]}"

    def limit():
        if file_limit:
            resource.setrlimit(resource.RLIMIT_FSIZE, (file_limit, file_limit))

    p = subprocess.run([talus, "run", *args], env=env, capture_output=True, text=True,
                       timeout=300, preexec_fn=limit)
    return p.returncode, p.stderr.strip()


def fresh(name):
    d = work / name
    shutil.rmtree(d, ignore_errors=True)
    return d


def folder_intact(out, label):
    """Every file in the folder is whole: JSON parses, CSV rows are complete, every VTU in the
    series reads, and no temporary file is left behind."""
    check(not list(out.rglob("*.tmp")), f"{label}: temporary files left: {list(out.rglob('*.tmp'))}")
    if (out / "summary.json").exists():
        json.loads((out / "summary.json").read_text())
    for csv in out.glob("*.csv"):
        lines = csv.read_text().splitlines()
        width = lines[0].count(",")
        check(all(line.count(",") == width for line in lines),
              f"{label}: {csv.name} has a torn row")
    if (out / "particles.pvd").exists():
        import xml.etree.ElementTree as ET
        for ds in ET.parse(out / "particles.pvd").getroot().iter("DataSet"):
            mesh = meshio.read(out / ds.get("file"))
            check(len(mesh.points) > 0, f"{label}: {ds.get('file')} is empty")


def sha(path):
    return hashlib.sha256(path.read_bytes()).hexdigest()


# 1. A blow-up: a fixed time step 25 times the CFL limit.
out = fresh("unstable")
code, err = run([str(case), "--out", str(out), "--set", "simulation.dt=0.01",
                 "--set", "checkpoint.every=0.01", "--set", "output.every=0.01"])
print("unstable:", err.splitlines()[-1] if err else "(no message)")
check(code == 1, f"unstable: exit {code}, expected 1")
for part in ("step ", "time ", "body '", "particle ", ") at (", "last good checkpoint: "):
    check(part in err, f"unstable: the message lacks '{part}': {err}")
check(any(w in err for w in ("det F", "not finite", "left the grid")),
      f"unstable: the message names no field: {err}")
summary = json.loads((out / "summary.json").read_text())
check(summary["status"] == "failed" and "particle" in summary.get("message", ""),
      f"unstable: summary.json status {summary['status']}")
folder_intact(out, "unstable")
# No frame written (one per step here) holds a non-finite value. This blow-up is caught by the
# det F check inside the step that inverts a particle, so it does not tell the end-of-step report
# of non-finite or off-grid particles from the old next-step check; BadState.StopsWithTheStep-
# ThatMadeIt (tests/unit/solver/particle_check_test.cpp) does, with one step().
import numpy as np
for vtu in sorted(out.glob("particles_*.vtu")):
    mesh = meshio.read(vtu)
    arrays = [mesh.points, *mesh.point_data.values()]
    check(all(np.isfinite(a).all() for a in arrays), f"unstable: {vtu.name} holds a non-finite value")

# 2. The CFL step collapsing below its floor.
out = fresh("collapse")
code, err = run([str(case), "--out", str(out), "--set", "simulation.dt_min=0.01"])
check(code == 1 and "time step collapsed" in err and "particle" in err,
      f"collapse: exit {code}: {err}")

# 3. A run folder that cannot be created (its parent is a file).
blocker = work / "a_file"
blocker.write_text("not a folder\n")
code, err = run([str(case), "--out", str(blocker / "run")])
check(code == 3 and "cannot create the run folder" in err, f"unwritable: exit {code}: {err}")

# 4. A full disk. A run interrupted at step 300 leaves a checkpoint; its restart under a file
#    size limit (frames fit, a checkpoint does not) must fail cleanly on its next checkpoint,
#    leave the old checkpoint untouched, and a second restart without the limit must finish
#    exactly as a run that never failed.
common = ["--set", "simulation.end_time=0.3", "--set", "checkpoint.every=0.1",
          "--set", "checkpoint.wall_minutes=0", "--set", "output.every=0.05",
          "--set", 'output.fields=["velocity"]']
ref = fresh("full_disk_reference")
code, err = run([str(case), "--out", str(ref), *common])
check(code == 0, f"full disk reference: exit {code}: {err}")
out = fresh("full_disk")
code, err = run([str(case), "--out", str(out), *common], inject=(signal.SIGINT, 300))
check(code == 128 + signal.SIGINT, f"full disk: the interrupted run exited {code}: {err}")
ckpts = sorted((out / "checkpoints").glob("*.ckpt"))
frame_size = (out / "particles_000000.vtu").stat().st_size
ckpt_size = ckpts[-1].stat().st_size
check(frame_size < ckpt_size, "full disk: the test needs frames smaller than checkpoints")
before = {p.name: sha(p) for p in ckpts}
limit = (frame_size + ckpt_size) // 2
code, err = run(["--restart", str(out)], file_limit=limit)
print("full disk:", err.splitlines()[-1] if err else "(no message)")
check(code == 3 and "File too large" in err and ".ckpt" in err,
      f"full disk: exit {code}, expected 3 with the checkpoint named: {err}")
after = {p.name: sha(p) for p in sorted((out / "checkpoints").glob("*.ckpt"))}
check(after == before, f"full disk: checkpoints changed: {before} -> {after}")
summary = json.loads((out / "summary.json").read_text())
check(summary["status"] == "failed" and "File too large" in summary.get("message", ""),
      f"full disk: summary.json says {summary['status']}")
folder_intact(out, "full disk")
code, err = run(["--restart", str(out)])
check(code == 0, f"full disk: the second restart exited {code}: {err}")
for f in sorted(ref.glob("*.csv")) + sorted(ref.glob("*.vtu")) + [ref / "particles.pvd"]:
    check((out / f.name).read_bytes() == f.read_bytes(),
          f"full disk: {f.name} differs from the run that never failed")

for f in failures:
    print("FAIL", f)
sys.exit(1 if failures else 0)
