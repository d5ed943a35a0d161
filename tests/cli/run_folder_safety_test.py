#!/usr/bin/python3
"""A run never loses or mixes a user's files, and never waits forever on an input:
- --overwrite empties only a folder that holds talus's marker (.talus-run), and only if every
  entry in it is talus's: a project folder with a case.toml, another tool's summary.json, or a
  run folder where the user added notes are refused with nothing removed;
- a run holds its folder: a second run (--overwrite) or a --restart into a folder whose run is
  still going is refused, naming the first; after a kill -9 the lock is gone and --restart works;
- a run folder deleted mid-run stops the run with an output error (exit 3), not "completed";
- a link planted at a temporary's name (RUN/summary.json.tmp) is never written through;
- an input copied into inputs/ keeps its permissions (a mode-600 polygon stays 600);
- a device, a FIFO, a folder or a VRT as an input file is refused at once (exit 2);
- a folder, link or FIFO named like a checkpoint is neither read nor pruned in a real one's place;
- SIGHUP stops a run with a checkpoint, as SIGINT does; --max-steps counts from a restart;
- the process is named talus in ps, and runs with OpenMP's passive wait policy.

Usage: run_folder_safety_test.py TALUS SOURCE_DIR WORK_DIR
"""
import json
import os
import shutil
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

talus, source, work = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
case = source / "cases/examples/block_on_floor.toml"
short = ["--set", "simulation.end_time=0.1", "--set", "output.every=0.02"]
endless = ["--set", "simulation.end_time=1000", "--set", "output.every=0.05"]
failures = []


def run(*args, timeout=300):
    p = subprocess.run([talus, "run", *map(str, args)], capture_output=True, text=True,
                       timeout=timeout)
    return p.returncode, p.stdout + p.stderr


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def start(*args):
    return subprocess.Popen([talus, "run", *map(str, args)], stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True)


def finish(p, seconds=120):
    """Waits for a started run (killing it after `seconds`) and returns its stderr."""
    try:
        p.wait(timeout=seconds)
    except subprocess.TimeoutExpired:
        p.kill()
        p.wait()
    return p.stderr.read()


def wait_for(path, seconds=60):
    deadline = time.time() + seconds
    while time.time() < deadline and not path.exists():
        time.sleep(0.05)
    return path.exists()


def listing(d):
    return sorted(str(p.relative_to(d)) for p in d.rglob("*"))


shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)

# A project folder whose case is named case.toml: never emptied, even with --overwrite.
project = work / "project"
project.mkdir()
shutil.copy(case, project / "case.toml")
shutil.copy(case.parent / "wedge.csv", project / "wedge.csv")
(project / "notes.txt").write_text("my notes\n")
before = listing(project)
code, out = run(project / "case.toml", "--out", project, "--overwrite", *short)
check(code == 2 and listing(project) == before and "not a talus run folder" in out,
      f"a project folder with a case.toml is refused by --overwrite, nothing removed (exit {code})")

# Another tool's summary.json: not a run folder.
other = work / "other_tool"
other.mkdir()
(other / "summary.json").write_text('{"tool": "not talus"}\n')
code, out = run(case, "--out", other, "--overwrite", *short)
check(code == 2 and (other / "summary.json").read_text() == '{"tool": "not talus"}\n',
      f"another tool's summary.json is kept (exit {code})")

# A run folder where the user added a file: --overwrite refuses, naming it, and removes nothing.
d = work / "added"
code, _ = run(case, "--out", d, *short)
check(code == 0 and (d / ".talus-run").is_file(), f"a run writes its marker (exit {code})")
(d / "notes.txt").write_text("mine\n")
before = listing(d)
code, out = run(case, "--out", d, "--overwrite", *short)
check(code == 2 and "notes.txt" in out and listing(d) == before,
      f"--overwrite refuses a run folder holding a user's file, nothing removed (exit {code}): "
      f"{out.strip()[-160:]}")
(d / "notes.txt").unlink()
code, out = run(case, "--out", d, "--overwrite", *short)
check(code == 0, f"--overwrite of a run folder of talus's files alone (exit {code})")
# A user's file in the run's inputs/: talus's copies are those its case.toml names.
check((d / "inputs/wedge.csv").is_file(), "the run copied its polygon into inputs/")
(d / "inputs/mine.csv").write_text("x,y\n")
code, out = run(case, "--out", d, "--overwrite", *short)
check(code == 2 and "inputs/mine.csv" in out and (d / "inputs/mine.csv").is_file(),
      f"--overwrite refuses a run folder with a user's file in inputs/, nothing removed (exit "
      f"{code}): {out.strip()[-160:]}")
(d / "inputs/mine.csv").unlink()
code, out = run(case, "--out", d, "--overwrite", *short)
check(code == 0, f"--overwrite once the user's file is gone (exit {code})")

# A run holds its folder: a second run and a restart are refused while it goes; kill -9 frees it.
busy = work / "busy"
p = start(case, "--out", busy, *endless, "--set", "checkpoint.every=0.05")
check(wait_for(busy / "checkpoints/step_0000000000.ckpt", 60) or
      wait_for(busy / "summary.json", 60), "the long run started")
time.sleep(1.0)
while p.poll() is None and not list((busy / "checkpoints").glob("*.ckpt")):
    time.sleep(0.1)
check(p.poll() is None, f"the long run is still going (exit {p.poll()}: "
      f"{p.stderr.read()[-300:] if p.poll() is not None else ''})")
code, out = run(case, "--out", busy, "--overwrite", *short)
check(code == 2 and f"talus process {p.pid}" in out and p.poll() is None,
      f"--overwrite onto a running run's folder is refused, naming it (exit {code}): "
      f"{out.strip()[-200:]}")
code, out = run("--restart", busy)
check(code == 2 and "in use" in out and p.poll() is None,
      f"--restart of a running run's folder is refused (exit {code}): {out.strip()[-160:]}")
p.send_signal(signal.SIGKILL)
p.wait()
code, out = run("--restart", busy, "--max-steps", "5")
check(code == 0 and "stopped after" in out, f"after kill -9 the folder is free: --restart works "
      f"(exit {code}): {out.strip()[-200:]}")
# --max-steps counts the restart's own steps.
s0 = json.loads((busy / "summary.json").read_text())["steps"]
code, out = run("--restart", busy, "--max-steps", "7")
s1 = json.loads((busy / "summary.json").read_text())["steps"]
check(code == 0 and s1 - s0 == 7, f"--max-steps 7 on a restart takes 7 more steps ({s0} -> {s1})")

# The run folder deleted mid-run: an output error, not success, and no partial folder left.
gone = work / "gone"
p = start(case, "--out", gone, *endless)
wait_for(gone / "particles_000001.vtu", 60)
# The run may add a file between rmtree's listing and its rmdir: remove until the folder is gone.
for _ in range(100):
    shutil.rmtree(gone, ignore_errors=True)
    if not gone.exists():
        break
    time.sleep(0.05)
check(not gone.exists(), "the run folder could be removed")
err = finish(p)
check(p.returncode == 3 and "removed" in err,
      f"a run whose folder is deleted stops with exit 3 (got {p.returncode}): {err.strip()[-200:]}")
check(not (gone / "summary.json").exists(), "no partial run folder is written in its place")

# The run folder moved away and a user's folder put at its path: the run writes on into the
# folder it took (held open), never into the user's, and stops with exit 3.
taken = work / "taken"
p = start(case, "--out", taken, *endless)
wait_for(taken / "particles_000001.vtu", 60)
taken.rename(work / "taken_moved")
taken.mkdir()
(taken / "notes.txt").write_text("mine\n")
for _ in range(50):  # let the run write a few more frames
    if p.poll() is not None:
        break
    time.sleep(0.1)
err = finish(p)
check(p.returncode == 3 and sorted(x.name for x in taken.iterdir()) == ["notes.txt"],
      f"a folder put in a run folder's place receives nothing (exit {p.returncode}, holds "
      f"{sorted(x.name for x in taken.iterdir())})")

# A link planted at a temporary's name is not followed.
planted = work / "planted"
code, _ = run(case, "--out", planted, *short, "--max-steps", "10")
victim = work / "victim.txt"
victim.write_text("precious\n")
os.symlink(victim, planted / "summary.json.tmp")
os.symlink(victim, planted / "energy.csv.tmp")
code, out = run("--restart", planted)
check(code == 0 and victim.read_text() == "precious\n",
      f"a restart never writes through a link at RUN/summary.json.tmp (exit {code})")

# An input's copy keeps its permissions.
src = work / "private"
src.mkdir()
shutil.copy(case, src / "case.toml")
shutil.copy(case.parent / "wedge.csv", src / "wedge.csv")
os.chmod(src / "wedge.csv", 0o600)
code, _ = run(src / "case.toml", "--out", work / "private_run", *short)
mode = stat.S_IMODE(os.stat(work / "private_run/inputs/wedge.csv").st_mode)
check(code == 0 and mode == 0o600, f"a mode-600 input is copied as {oct(mode)}")

# Inputs that are not regular files, or a VRT: refused at once, naming the key.
os.mkfifo(work / "fifo.csv")
(work / "folder.csv").mkdir()
(work / "virtual.asc").write_text('<VRTDataset rasterXSize="2" rasterYSize="2"></VRTDataset>\n')
text = case.read_text()
check('"wedge.csv"' in text, "the case reads wedge.csv")
for name, bad in [("device", "/dev/zero"), ("fifo", str(work / "fifo.csv")),
                  ("folder", str(work / "folder.csv"))]:
    bad_case = work / f"bad_{name}.toml"
    bad_case.write_text(text.replace('"wedge.csv"', f'"{bad}"'))
    t0 = time.time()
    code, out = run(bad_case, "--out", work / f"bad_{name}", *short, timeout=60)
    check(code == 2 and time.time() - t0 < 30 and "polygon" in out,
          f"a {name} as the polygon file is refused at once (exit {code}): {out.strip()[-160:]}")
volcano = source / "cases/examples/volcano_slide.toml"
if volcano.exists():
    vtext = volcano.read_text()
    raster = next((w for w in vtext.split('"') if w.endswith((".asc", ".tif"))), None)
    if raster:
        vcase = work / "vrt.toml"
        for f in (volcano.parent).glob("*"):
            if f.is_file() and f.name != volcano.name:
                shutil.copy(f, work / f.name)
        vcase.write_text(vtext.replace(f'"{raster}"', '"virtual.asc"', 1))
        code, out = run(vcase, "--out", work / "vrt_run", timeout=60)
        check(code == 2 and "VRT" in out, f"a VRT raster is refused (exit {code}): "
              f"{out.strip()[-160:]}")

# A folder, link or FIFO named like a newer checkpoint: skipped, and pruning keeps the real ones.
ck = work / "ck"
code, _ = run(case, "--out", ck, *short, "--max-steps", "20", "--set", "checkpoint.keep=1")
real = sorted((ck / "checkpoints").glob("*.ckpt"))
(ck / "checkpoints/step_9999999990.ckpt").mkdir()
os.symlink(real[-1], ck / "checkpoints/step_9999999991.ckpt")
os.mkfifo(ck / "checkpoints/step_9999999992.ckpt")
code, out = run("--restart", ck, "--max-steps", "5", timeout=60)
left = sorted(p.name for p in (ck / "checkpoints").iterdir())
check(code == 0 and "step_9999999990.ckpt" in left and "step_9999999991.ckpt" in left
      and any(n < "step_9" for n in left),
      f"a stray folder, link and FIFO named as checkpoints are skipped and kept (exit {code}): {left}")

# SIGHUP: a checkpoint and status interrupted, as for SIGINT.
hup = work / "hup"
p = start(case, "--out", hup, *endless)
wait_for(hup / "particles_000001.vtu", 60)
comm = Path(f"/proc/{p.pid}/comm").read_text().strip() if p.poll() is None else ""
check(comm == "talus", f"the process is named talus in ps (comm {comm!r})")
# Idle OpenMP threads sleep: the program re-executes itself with OMP_WAIT_POLICY=passive.
environ = Path(f"/proc/{p.pid}/environ").read_bytes().split(b"\0") if p.poll() is None else []
check(b"OMP_WAIT_POLICY=passive" in environ or "OMP_WAIT_POLICY" in os.environ,
      "the run's OpenMP threads wait passively (OMP_WAIT_POLICY=passive in its environment)")
p.send_signal(signal.SIGHUP)
p.wait(timeout=60)
s = json.loads((hup / "summary.json").read_text())
check(p.returncode == 128 + signal.SIGHUP and s["status"] == "interrupted"
      and list((hup / "checkpoints").glob("*.ckpt")),
      f"SIGHUP stops with a checkpoint (exit {p.returncode}, status {s['status']})")

# A frame the checkpoint lists, deleted: the restart refuses to continue the folder (it would end
# "completed" with particles.pvd listing a file that is not there), and writes nothing.
gone = work / "frame_gone"
code, _ = run(case, "--out", gone, *short, "--max-steps", "20")
check(code == 0 and (gone / "particles_000000.vtu").is_file(), f"a stopped run (exit {code})")
(gone / "particles_000000.vtu").unlink()
before = listing(gone)
code, out = run("--restart", gone)
check(code == 2 and "particles_000000.vtu: a frame the checkpoint lists is missing" in out
      and not (gone / "particles_000000.vtu").exists(),
      f"a restart with a listed frame deleted is refused (exit {code}): {out.strip()[-160:]}")

# A run killed while it copies its inputs leaves a folder of talus's files alone: case.toml, which
# names the copies, is written before them, so --overwrite (and a sweep's resume) can empty it.
volcano = (source / "cases/examples/volcano_slide.toml").read_text().replace(
    '"volcano/', f'"{source}/cases/examples/volcano/')
(work / "volcano.toml").write_text(volcano)
for attempt in range(5):
    cut = work / f"cut_in_copies_{attempt}"
    p = start(work / "volcano.toml", "--out", cut, "--set", "simulation.end_time=0.01")
    while p.poll() is None and not (cut / "inputs").is_dir():
        pass
    p.send_signal(signal.SIGKILL)
    p.wait(timeout=60)
    code, out = run(work / "volcano.toml", "--out", cut, "--overwrite", "--set",
                    "simulation.end_time=0.01", "--set", "output.particles=false")
    check(code == 0, f"a run killed among its input copies is taken by --overwrite (exit {code}): "
          f"{out.strip()[-240:]}")

print(f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
