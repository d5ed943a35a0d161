#!/usr/bin/python3
"""Run folders that never mix or lose a run (issue 24):
- a fresh run refuses a folder that holds an earlier run (exit 2) and, with --overwrite, empties
  it first: no stale frame of the earlier run is left;
- a folder that is not a run folder is refused even with --overwrite, and its files are kept;
- --max-steps stops with status "stopped" and a checkpoint, and --restart continues it to the
  same bits as a run that never stopped;
- --restart refuses a checkpoint of another case than the folder's case.toml;
- summary.json exists with status "running" from the first step on (a run killed outright still
  says it started);
- --max-steps must be a positive number of steps;
- the run folder is self-contained: case.toml is the case as written (comments and all) with a
  [[run]] entry of the --set values, the polygon CSV is copied into inputs/, `talus run
  RUN/case.toml` from another directory gives the same bits, and --restart works from another
  directory after the original case and its CSV are deleted and the run folder moved.

Usage: run_folder_integrity_test.py TALUS SOURCE_DIR WORK_DIR
"""
import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

talus, source, work = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
case = source / "cases/examples/block_on_floor.toml"
short = ["--set", "simulation.end_time=0.1", "--set", "output.every=0.02"]
failures = []


def run(*args):
    p = subprocess.run([talus, "run", *map(str, args)], capture_output=True, text=True,
                       timeout=600)
    return p.returncode, p.stdout + p.stderr


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def frames(d):
    return sorted(p.name for p in d.glob("particles_*.vtu"))


shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)

# A reused folder: refused, then emptied with --overwrite (fewer frames: none left over).
d = work / "reused"
code, out = run(case, "--out", d, *short)
check(code == 0 and len(frames(d)) == 6, f"first run: exit {code}, frames {frames(d)}")
code, out = run(case, "--out", d, "--set", "simulation.end_time=0.04", "--set", "output.every=0.02")
check(code == 2 and "holds an earlier run" in out and len(frames(d)) == 6,
      f"a reused folder is refused (exit {code}): {out.strip()[-200:]}")
code, out = run(case, "--out", d, "--overwrite", "--set", "simulation.end_time=0.04",
                "--set", "output.every=0.02")
check(code == 0 and frames(d) == ["particles_000000.vtu", "particles_000001.vtu",
                                  "particles_000002.vtu"],
      f"--overwrite empties it first (exit {code}): {frames(d)}")

# Not a run folder: never emptied.
d = work / "not_a_run"
d.mkdir()
(d / "notes.txt").write_text("mine\n")
code, out = run(case, "--out", d, "--overwrite", *short)
check(code == 2 and (d / "notes.txt").exists() and "not a talus run folder" in out,
      f"a folder of other files is refused even with --overwrite (exit {code})")

# --max-steps: stopped, with a checkpoint; --restart continues it bitwise.
ref, stopped = work / "ref", work / "stopped"
code, _ = run(case, "--out", ref, *short)
check(code == 0, f"reference run: exit {code}")
code, out = run(case, "--out", stopped, *short, "--max-steps", "40")
summary = json.loads((stopped / "summary.json").read_text())
check(code == 0 and summary["status"] == "stopped" and summary["steps"] == 40
      and list((stopped / "checkpoints").glob("*")) and "--restart" in out,
      f"--max-steps 40: exit {code}, status {summary['status']}, steps {summary['steps']}")
code, out = run("--restart", stopped)
summary = json.loads((stopped / "summary.json").read_text())
check(code == 0 and summary["status"] == "completed", f"restarted: exit {code}, {out[-200:]}")
for f in ["energy.csv", "bodies.csv", "contacts.csv"] + frames(ref):
    check((ref / f).read_bytes() == (stopped / f).read_bytes(), f"{f} identical after the stop")

# A checkpoint of another case: refused.
other = work / "other"
code, _ = run(case, "--out", other, *short, "--max-steps", "10")
text = (other / "case.toml").read_text()
edited = text.replace("simulation.end_time=0.1", "simulation.end_time=0.2")
check(edited != text, "case.toml holds the run's --set values")
(other / "case.toml").write_text(edited)
code, out = run("--restart", other)
check(code == 2 and "another case" in out, f"a foreign checkpoint is refused (exit {code}): "
      f"{out.strip()[-200:]}")

# summary.json from the first step: a run killed outright still says it started.
killed = work / "killed"
p = subprocess.Popen([talus, "run", str(case), "--out", str(killed), "--set",
                      "simulation.end_time=100"], stdout=subprocess.DEVNULL,
                     stderr=subprocess.DEVNULL)
deadline = time.time() + 60
while time.time() < deadline and not (killed / "summary.json").exists():
    time.sleep(0.05)
time.sleep(0.5)
p.send_signal(signal.SIGKILL)
p.wait()
s = json.loads((killed / "summary.json").read_text()) if (killed / "summary.json").exists() else {}
check(s.get("status") == "running", f"killed run's summary.json says running: {s.get('status')}")

# kill -9 in the first minute, with the default checkpoint settings: the first wall-clock
# checkpoint (after 30 s) is there, and the restarted run ends as the one never killed.
long = ["--set", "simulation.end_time=40", "--set", "output.every=5"]  # ~70 s here
ref_long, killed = work / "ref_long", work / "killed_long"
reference = subprocess.Popen([talus, "run", str(case), "--out", str(ref_long), *long],
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
p = subprocess.Popen([talus, "run", str(case), "--out", str(killed), *long],
                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
start = time.time()
while time.time() - start < 58 and not list((killed / "checkpoints").glob("*.ckpt")):
    time.sleep(0.2)
time.sleep(0.5)
p.send_signal(signal.SIGKILL)
p.wait()
killed_at = time.time() - start
check(killed_at < 60 and list((killed / "checkpoints").glob("*.ckpt")),
      f"a checkpoint within the first minute (killed after {killed_at:.0f} s)")
code, out = run("--restart", killed)
reference.wait()
check(code == 0 and reference.returncode == 0, f"restarted after kill -9: exit {code}")
for f in ["energy.csv", "bodies.csv", "contacts.csv"] + frames(ref_long):
    check((ref_long / f).read_bytes() == (killed / f).read_bytes(),
          f"{f} identical after kill -9 and restart")

# Names in the CSVs are quoted as RFC 4180 requires: a body named "a,b" and a probe named
# 'say "hi"' keep every row at the header's width.
import csv
quoted = work / "quoted.toml"
shutil.copy(case.parent / "wedge.csv", work / "wedge.csv")  # the case's polygon, beside it
text = case.read_text().replace('name = "block"', 'name = "a,b"').replace('body = "block"',
                                                                           'body = "a,b"')
quoted.write_text(text.replace('name = "block_top"', "name = 'say \"hi\"'"))
code, out = run(quoted, "--out", work / "quoted", *short)
for table in ["bodies.csv", "probes.csv"]:
    rows = list(csv.reader(open(work / "quoted" / table)))
    widths = {len(r) for r in rows}
    names = {r[1] for r in rows[1:]}
    check(code == 0 and len(widths) == 1 and ("a,b" in names or 'say "hi"' in names),
          f"{table}: rows of one width {widths}, names {sorted(names)[:3]}")

# Self-contained: the case and its CSV in a folder of their own, which is then deleted.
src = work / "source"
src.mkdir()
shutil.copy(case, src / case.name)
shutil.copy(case.parent / "wedge.csv", src / "wedge.csv")
own, again, elsewhere = work / "own", work / "again", work / "elsewhere"
elsewhere.mkdir()
code, _ = run(src / case.name, "--out", own, *short, "--max-steps", "40")
written = (own / "case.toml").read_text()
check(code == 0 and written.startswith(case.read_text()) and "[[run]]" in written
      and "'simulation.end_time=0.1'" in written and "inputs/wedge.csv" in written,
      "case.toml: the case as written, then a [[run]] entry of the --set values and the copies")
check((own / "inputs/wedge.csv").read_bytes() == (case.parent / "wedge.csv").read_bytes(),
      "the polygon CSV is copied into inputs/")
shutil.rmtree(src)
moved = work / "moved"
own.rename(moved)
p = subprocess.run([talus, "run", "--restart", str(moved)], cwd=elsewhere, capture_output=True,
                   text=True, timeout=600)
check(p.returncode == 0, f"--restart from another directory after the source is deleted and the "
      f"folder moved: exit {p.returncode} {(p.stdout + p.stderr)[-300:]}")
for f in ["energy.csv", "bodies.csv", "contacts.csv"] + frames(ref):
    check((ref / f).read_bytes() == (moved / f).read_bytes(), f"{f} identical after the move")
p = subprocess.run([talus, "run", str(moved / "case.toml"), "--out", str(again)], cwd=elsewhere,
                   capture_output=True, text=True, timeout=600)
check(p.returncode == 0 and (again / "case.toml").read_text() == written,
      f"RUN/case.toml runs again from another directory (exit {p.returncode}) and adds nothing")
for f in ["energy.csv", "bodies.csv", "contacts.csv"] + frames(ref):
    check((ref / f).read_bytes() == (again / f).read_bytes(), f"{f} identical from RUN/case.toml")

# --max-steps takes a positive count.
for bad in ["0", "-1"]:
    code, out = run(case, "--out", work / "bad", "--max-steps", bad)
    check(code != 0 and "max-steps" in out, f"--max-steps {bad} refused (exit {code})")

print(f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
