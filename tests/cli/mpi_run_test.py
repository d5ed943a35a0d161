#!/usr/bin/env python3
"""`mpirun -np N talus run`: the run folder of the coarse three-body Vaiont (contact, cohesive
interfaces that degrade with slip and cross the slab cuts, settling, probes, frames) on 2, 3
and 4 processes x 1 and 2 threads is byte for byte the one-process run's: every CSV, every VTU
frame (particles, streamed to rank 0, and contact nodes), the ParaView series, and the results
in summary.json. Then: a run stopped on 2 processes
(--max-steps), its newest checkpoint damaged, and restarted on 3 ends identical (each process
reading its slab of the older checkpoint); a process killed with SIGKILL stops the others
and leaves its newest checkpoint readable, and a one-process restart from it ends identical; the
3D volcano slide's hazard maps (GeoTIFFs) on 2 and 3 processes are the one-process run's, and a
mapped particle too fast for the maps stops every process; a slide into water (a fluid body)
on 3 processes is the one-process run; an APIC run stopped on 2 processes and restarted on 3 is
the one-process run;
a grid too narrow for the processes is refused with a message naming its columns; a bad case's
error is printed once, not once per process.

Usage: mpi_run_test.py TALUS_SERIAL TALUS_MPI MPIEXEC SOURCE_DIR WORK_DIR
"""
import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

serial, talus, mpiexec, source, work = sys.argv[1:4] + [Path(sys.argv[4]), Path(sys.argv[5])]
case = source / "cases/vaiont/three_bodies.toml"
settings = ["grid.cell_size=16", "initial_state.settle_time=1.0", "simulation.end_time=2.0",
            "output.every=0.5", "output.particles=true", "output.contact_nodes=true",
            "checkpoint.every=0.5",
            "checkpoint.wall_minutes=0"]
failures = []
env = dict(os.environ, OMP_WAIT_POLICY="passive", OMPI_ALLOW_RUN_AS_ROOT="1",
           OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def mpi(np, threads):
    return [mpiexec, "--oversubscribe", "--mca", "mpi_yield_when_idle", "1", "-x",
            "OMP_WAIT_POLICY", "-np", str(np), talus]


def args(out, extra=()):
    a = ["run", str(case), "--out", str(out), *extra]
    for s in settings:
        a += ["--set", s]
    return a


def run(cmd, threads, timeout=900):
    p = subprocess.run([*cmd, "--threads", str(threads)], env=env, capture_output=True,
                       text=True, timeout=timeout)
    return p.returncode, p.stdout + p.stderr


def fresh(name):
    d = work / name
    shutil.rmtree(d, ignore_errors=True)
    return d


def compare(ref, other, label):
    names = sorted(p.name for p in ref.iterdir() if p.suffix in (".csv", ".vtu", ".pvd"))
    if not any(n.endswith(".vtu") for n in names):
        failures.append(f"{label}: the reference run wrote no frames")
    for n in names:
        if not (other / n).exists() or (ref / n).read_bytes() != (other / n).read_bytes():
            failures.append(f"{label}: {n} differs from the one-process run")
    results = lambda d: json.loads((d / "summary.json").read_text())["results"]
    if results(ref) != results(other):
        failures.append(f"{label}: summary.json results differ: {results(other)}")


work.mkdir(parents=True, exist_ok=True)
ref = fresh("one")
rc, out = run([serial, *args(ref)], 2)
if rc != 0:
    sys.exit(f"the one-process run failed ({rc}): {out}")

for np in (2, 3, 4):
    for threads in (1, 2):
        d = fresh(f"np{np}_t{threads}")
        rc, out = run([*mpi(np, threads), *args(d)], threads)
        if rc != 0:
            failures.append(f"{np} processes x {threads} threads: exit {rc}: {out[-2000:]}")
            continue
        if f"{np} processes x {threads} threads" not in out:
            failures.append(f"{np} x {threads}: the log does not name the processes: {out[:300]}")
        compare(ref, d, f"{np} processes x {threads} threads")

# Stopped on 2 processes (inside the run, past two checkpoints), restarted on 3.
d = fresh("two_then_three")
rc, out = run([*mpi(2, 1), *args(d, ["--max-steps", "120"])], 1)
if rc != 0 or "stopped after 120 steps" not in out:
    failures.append(f"stop on 2 processes: exit {rc}: {out[-1500:]}")
# The newest checkpoint damaged (one byte): every process skips it for the older one.
newest = sorted((d / "checkpoints").glob("*.ckpt"))[-1]
damaged = bytearray(newest.read_bytes())
damaged[len(damaged) // 2] ^= 1
newest.write_bytes(damaged)
rc, out = run([*mpi(3, 1), "run", "--restart", str(d)], 1)
if rc != 0:
    failures.append(f"restart on 3 processes: exit {rc}: {out[-1500:]}")
else:
    if f"skipping {newest}: corrupt checkpoint (checksum mismatch)" not in out:
        failures.append(f"restart on 3 processes: the damaged checkpoint not reported: {out[:800]}")
    compare(ref, d, "stopped on 2 processes, restarted on 3 from the older checkpoint")

# A process killed mid-run: mpirun stops the others; the newest checkpoint is whole.
d = fresh("killed")
p = subprocess.Popen([*mpi(2, 1), *args(d), "--threads", "1"], env=env,
                     stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
deadline = time.time() + 300
while time.time() < deadline and len(list((d / "checkpoints").glob("*.ckpt"))) < 2:
    time.sleep(0.05)
ranks = subprocess.run(["pgrep", "-f", f"{talus} run {case}"], capture_output=True, text=True)
pids = [int(x) for x in ranks.stdout.split()]
if not pids:
    failures.append("killed: no process of the run found")
else:
    os.kill(max(pids), signal.SIGKILL)
try:
    p.wait(timeout=120)
    if p.returncode == 0:
        failures.append("killed: mpirun reported success after a process was killed")
except subprocess.TimeoutExpired:
    p.kill()
    failures.append("killed: the other process did not stop within 120 s")
summary = json.loads((d / "summary.json").read_text())
if summary["status"] == "completed":
    failures.append("killed: the run completed although a process was killed")
rc, out = run([serial, "run", "--restart", str(d)], 2)
if rc != 0:
    failures.append(f"killed: one-process restart from the newest checkpoint: exit {rc}: {out}")
else:
    compare(ref, d, "killed on 2 processes, restarted on 1")

# A blow-up (a fixed step 25 times the CFL limit) on 2 processes: every process stops with the
# first failing process's message, and summary.json says "failed" with it, as on one process.
d = fresh("unstable")
rc, out = run([*mpi(2, 1), "run", str(source / "cases/examples/block_on_floor.toml"), "--out",
               str(d), "--set", "simulation.dt=0.01", "--set", "checkpoint.every=0.01"], 1,
              timeout=300)
summary = json.loads((d / "summary.json").read_text())
message = summary.get("message", "")
if rc != 1 or summary["status"] != "failed":
    failures.append(f"unstable: exit {rc}, status {summary['status']}: {out[-800:]}")
for part in ("process ", " of 2: step ", "time ", "particle ", "det F", "last good checkpoint: "):
    if part not in message:
        failures.append(f"unstable: the summary's message lacks '{part}': {message}")
# The particle is named as one process names it (its index in one process's order, its id).
d1 = fresh("unstable_one")
run([serial, "run", str(source / "cases/examples/block_on_floor.toml"), "--out", str(d1),
     "--set", "simulation.dt=0.01", "--set", "checkpoint.every=0.01"], 1, timeout=300)
one = json.loads((d1 / "summary.json").read_text()).get("message", "")
if message.replace("process 0 of 2: ", "").replace(str(d), str(d1)) != one:
    failures.append(f"unstable: 2 processes say '{message}', one process '{one}'")

# Hazard maps ([maps]) of the 3D volcano slide: the GeoTIFFs and outlines on 2 and 3 processes
# are the one-process run's, byte for byte (their cell sums are integers: exact in any order).
volcano = source / "cases/examples/volcano_slide.toml"
maps_settings = ["--set", 'maps.bodies=["slide"]', "--set", "initial_state.settle_time=0.5",
                 "--set", "simulation.end_time=2.0", "--set", "output.every=1.0", "--set",
                 "output.particles=false"]
d1 = fresh("maps_one")
rc, out = run([serial, "run", str(volcano), "--out", str(d1), *maps_settings], 2)
if rc != 0:
    failures.append(f"maps, one process: exit {rc}: {out[-800:]}")
for np in (2, 3):
    d = fresh(f"maps_np{np}")
    rc, out = run([*mpi(np, 1), "run", str(volcano), "--out", str(d), *maps_settings], 1)
    if rc != 0:
        failures.append(f"maps, {np} processes: exit {rc}: {out[-800:]}")
        continue
    tifs = sorted(p.name for p in (d1 / "maps").iterdir())
    if len(tifs) != 13:
        failures.append(f"maps: the one-process run wrote {tifs}")
    for n in tifs:
        if (d1 / "maps" / n).read_bytes() != (d / "maps" / n).read_bytes():
            failures.append(f"maps, {np} processes: maps/{n} differs from the one-process run")

# A mapped particle out of the maps' range on some processes only: every process stops with the
# first one's message (none waits in the maps' sums for a process that has stopped).
d = fresh("maps_too_fast")
rc, out = run([*mpi(3, 1), "run", str(volcano), "--out", str(d), *maps_settings, "--set",
               "initial_state.settle_time=0", "--set", "body.slide.velocity=[5000, 0, 0]"], 1,
              timeout=300)
summary = json.loads((d / "summary.json").read_text())
message = summary.get("message", "")
if rc != 1 or summary["status"] != "failed" or "faster than the 4096 m/s" not in message:
    failures.append(f"maps, a particle too fast: exit {rc}, {summary['status']}: {out[-800:]}")

# A grid too narrow for the processes' slabs.
d = fresh("narrow")
rc, out = run([*mpi(4, 1), "run", str(source / "cases/benchmarks/cohesive_block.toml"), "--out",
               str(d), "--set", "grid.cell_size=0.5"], 1)
if rc != 2 or "cell columns" not in out:
    failures.append(f"narrow grid: exit {rc}, expected 2 with the columns named: {out[-800:]}")

# Water as a body (a fluid, a slide into it, contact, surface gauges): on 3 processes the
# one-process run folder, waves.csv included.
fluid = ["--set", "grid.cell_size=0.05", "--set", "simulation.end_time=0.8", "--set",
         "output.every=0.2"]
fluid_case = str(source / "cases/examples/slide_into_tank.toml")


def reference(name, case_file, settings, threads):
    """The one-process run folder to compare with, or None (its failure recorded)."""
    d1 = fresh(name)
    rc, out = run([serial, "run", case_file, "--out", str(d1), *settings], threads)
    if rc != 0:
        failures.append(f"{name}: the one-process run: exit {rc}: {out[-1500:]}")
        return None
    return d1


d1 = reference("fluid_one", fluid_case, fluid, 2)
if d1:
    d = fresh("fluid_three")
    rc, out = run([*mpi(3, 1), "run", fluid_case, "--out", str(d), *fluid], 1)
    if rc != 0:
        failures.append(f"fluid on 3 processes: exit {rc}: {out[-1500:]}")
    else:
        compare(d1, d, "fluid on 3 processes")

# APIC (simulation.apic: each particle's affine velocity C through the exchange, the gathered
# checkpoint and a slab's restart): the disk of general_rolling_apic node by node, stopped on 2
# processes after 2000 of its 3262 steps (past three checkpoints, each gathered) and restarted
# on 3 from the checkpoint the stop wrote, is the one-process run.
apic_case = str(source / "cases/benchmarks/general_rolling_apic.toml")
apic = [x for kv in ("grid.cell_size=0.1", 'contact.0.law="nodes"', "contact.0.friction=10.0",
                     "simulation.gravity=[4.905, -8.49570921113]", "simulation.end_time=0.5",
                     "output.every=0.1", "output.particles=true", "checkpoint.every=0.1",
                     "checkpoint.wall_minutes=0") for x in ("--set", kv)]
d1 = reference("apic_one", apic_case, apic, 1)
if d1:
    d = fresh("apic_two_then_three")
    rc, out = run([*mpi(2, 1), "run", apic_case, "--out", str(d), *apic, "--max-steps", "2000"], 1)
    if rc != 0 or "stopped after 2000 steps" not in out:
        failures.append(f"APIC stopped on 2 processes: exit {rc}: {out[-1500:]}")
    else:
        rc, out = run([*mpi(3, 1), "run", "--restart", str(d)], 1)
        if rc != 0:
            failures.append(f"APIC restarted on 3 processes: exit {rc}: {out[-1500:]}")
        else:
            compare(d1, d, "APIC stopped on 2 processes, restarted on 3")

# A bad case: every process reads it and fails alike; the error is printed once.
d = fresh("bad_case")
rc, out = run([*mpi(3, 1), "run", str(case), "--out", str(d), "--set", "grid.cell_size=-1"], 1)
if rc != 2 or out.count("grid.cell_size: must be > 0") != 1:
    failures.append(f"bad case on 3 processes: exit {rc}, expected 2 and the error once: {out}")

if failures:
    print("\n".join(failures))
    sys.exit(1)
print("mpi run folders identical to the one-process run (2, 3, 4 processes x 1, 2 threads; "
      "2 -> 3 restart; killed process; blow-up reported as failed; hazard maps on 2 and 3 "
      "processes, and stopped on all when a particle is too fast; a fluid body on 3 processes; APIC "
      "stopped on 2 and restarted on 3; narrow grid refused; bad case reported once)")
