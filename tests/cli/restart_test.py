#!/usr/bin/env python3
"""Exact restart: a run stopped by SIGINT, SIGTERM or kill -9 (at steps chosen in the settling
phase and in the run proper, between checkpoints) and restarted with `talus run --restart`
must leave a run folder identical to a run that was never stopped: every CSV, every VTU frame
and the ParaView series byte for byte, and the same results in summary.json; also for a case
whose fixed body is written once (particles_fixed.vtu), and for a contact at surface points. The
interrupted and restarted runs use 1 and 2 threads crosswise, so this also checks the
deterministic scatter.

The faults are injected with TALUS_INJECT_SIGNAL=SIGNAL:STEP, which makes the program raise the
signal on itself right after that step (the handler path is the real one).

Usage: restart_test.py TALUS SOURCE_DIR WORK_DIR
"""
import json
import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

talus, source, work = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
case = source / "cases/vaiont/three_bodies.toml"
# Coarse Vaiont (16 m cells): three bodies, plasticity, cohesive interfaces that degrade,
# a settling phase, probes; checkpoints every 0.5 s of simulated time, output every 0.25 s with
# the contact nodes (restored from a checkpoint for a frame written before the next step).
settings = ["grid.cell_size=16", "initial_state.settle_time=1.5", "simulation.end_time=2.5",
            "output.every=0.25", "output.contact_nodes=true", "checkpoint.every=0.5",
            "checkpoint.wall_minutes=0"]
failures = []


def run(args, threads, inject=None):
    env = dict(os.environ)
    env.pop("TALUS_INJECT_SIGNAL", None)
    if inject:
        env["TALUS_INJECT_SIGNAL"] = f"{int(inject[0])}:{inject[1]}"
    p = subprocess.run([talus, "run", *args, "--threads", str(threads)], env=env,
                       capture_output=True, text=True, timeout=600)
    return p.returncode, p.stderr


def fresh(name):
    d = work / name
    shutil.rmtree(d, ignore_errors=True)
    return d


def case_args(out):
    args = [str(case), "--out", str(out)]
    for s in settings:
        args += ["--set", s]
    return args


def compare(ref, other, label):
    names = sorted(p.name for p in ref.iterdir() if p.suffix in (".csv", ".vtu", ".pvd"))
    for n in names:
        if not (other / n).exists() or (ref / n).read_bytes() != (other / n).read_bytes():
            failures.append(f"{label}: {n} differs from the uninterrupted run")
    extra = sorted(p.name for p in other.iterdir() if p.suffix in (".csv", ".vtu", ".pvd")
                   and p.name not in names)
    if extra:
        failures.append(f"{label}: files the uninterrupted run does not have: {extra}")
    a, b = json.loads((ref / "summary.json").read_text()), json.loads(
        (other / "summary.json").read_text())
    for key in ("status", "steps", "simulated_time", "results"):
        if a[key] != b[key]:
            failures.append(f"{label}: summary.json {key}: {b[key]} != {a[key]}")
    leftovers = [p.name for p in other.rglob("*.tmp")]
    if leftovers:
        failures.append(f"{label}: temporary files left behind: {leftovers}")
    print(f"{label}: compared {len(names)} files and summary.json")


ref = fresh("reference")
code, err = run(case_args(ref), 2)
assert code == 0, f"reference run failed ({code}): {err}"
total = json.loads((ref / "summary.json").read_text())["steps"]
rows = len((ref / "energy.csv").read_text().splitlines())
print(f"reference: {total} steps, {rows - 1} output rows")
settle_steps = None
# Steps of the faults: during settling, in the run proper, and late in it.
plan = [("sigint_settling", signal.SIGINT, total // 4, 1, 2),
        ("sigterm_running", signal.SIGTERM, (3 * total) // 4, 2, 1),
        ("kill9_running", signal.SIGKILL, (2 * total) // 3, 1, 2),
        ("kill9_damaged_newest", signal.SIGKILL, (5 * total) // 6, 2, 2)]
for label, sig, step, t1, t2 in plan:
    out = fresh(label)
    code, err = run(case_args(out), t1, (sig, step))
    ckpts = sorted((out / "checkpoints").glob("step_*.ckpt"))
    if sig == signal.SIGKILL:
        if code != -signal.SIGKILL:
            failures.append(f"{label}: expected death by SIGKILL, got exit {code}")
        # The killed run wrote output after its last checkpoint: restart must drop those rows.
        if not ckpts:
            failures.append(f"{label}: no checkpoint before the kill")
            continue
        if label == "kill9_damaged_newest":
            if len(ckpts) < 2:
                failures.append(f"{label}: only {len(ckpts)} checkpoint(s) kept")
                continue
            data = ckpts[-1].read_bytes()
            ckpts[-1].write_bytes(data[: len(data) // 2])  # a torn write on a lying disk
    else:
        if code != 128 + sig:
            failures.append(f"{label}: exit {code}, expected {128 + sig} ({err.strip()})")
        summary = json.loads((out / "summary.json").read_text())
        if summary["status"] != "interrupted" or summary["steps"] != step:
            failures.append(f"{label}: summary status {summary['status']} at step "
                            f"{summary['steps']}, expected interrupted at {step}")
        if "--restart" not in err or not ckpts or f"step_{step:010d}" not in ckpts[-1].name:
            failures.append(f"{label}: no checkpoint at step {step} or no hint: {err.strip()}")
    if len(ckpts) > 2:
        failures.append(f"{label}: {len(ckpts)} checkpoints kept, expected the last 2")
    code, err = run(["--restart", str(out)], t2)
    if code != 0:
        failures.append(f"{label}: restart failed ({code}): {err.strip()}")
        continue
    compare(ref, out, label)

# A case with a fixed body (the rigid boundary) writes it once, into particles_fixed.vtu at its
# first frame; a restart continues the folder without writing it again, and the folder is the
# uninterrupted run's.
case = source / "cases/vaiont/rigid_boundary.toml"
ref = fresh("fixed_reference")
code, err = run(case_args(ref), 2)
assert code == 0, f"fixed-body reference run failed ({code}): {err}"
total = json.loads((ref / "summary.json").read_text())["steps"]
if not (ref / "particles_fixed.vtu").is_file():
    failures.append("fixed_reference: no particles_fixed.vtu")
# A stop while settling: no frame yet, so the restarted run writes the fixed part at its first.
for label, sig, step, t1, t2 in [("fixed_sigint_settling", signal.SIGINT, 5, 1, 2),
                                 ("fixed_sigterm", signal.SIGTERM, total // 2, 2, 1),
                                 ("fixed_kill9", signal.SIGKILL, (3 * total) // 4, 1, 2)]:
    out = fresh(label)
    run(case_args(out), t1, (sig, step))
    fixed = out / "particles_fixed.vtu"
    written = fixed.stat().st_mtime_ns if fixed.exists() else None
    code, err = run(["--restart", str(out)], t2)
    if code != 0:
        failures.append(f"{label}: restart failed ({code}): {err.strip()}")
        continue
    if written is not None and fixed.stat().st_mtime_ns != written:
        failures.append(f"{label}: the restart wrote particles_fixed.vtu again")
    compare(ref, out, label)

# Contact at surface points (law = "surface"): the points are rebuilt from the particles' first
# positions on a restart, and the run continues to the same bits (a disk rolling at mu 10,
# settled with its contact held, then released); under FLIP with GIMP, and under APIC with
# B-splines (the particles' affine velocities are in the checkpoint).
for name in ("general_rolling", "general_rolling_apic"):
    case = source / f"cases/benchmarks/{name}.toml"
    settings = ["grid.cell_size=0.1", "contact.0.friction=10",
                "simulation.gravity=[4.905, -8.49570921113]", "initial_state.settle_time=0.1",
                "initial_state.hold_contacts=true", "simulation.end_time=0.4", "output.every=0.05",
                "output.particles=true", "checkpoint.every=0.1", "checkpoint.wall_minutes=0"]
    ref = fresh(f"{name}_reference")
    code, err = run(case_args(ref), 2)
    assert code == 0, f"{name} reference run failed ({code}): {err}"
    total = json.loads((ref / "summary.json").read_text())["steps"]
    for label, sig, step, t1, t2 in [(f"{name}_sigterm", signal.SIGTERM, total // 2, 1, 2),
                                     (f"{name}_kill9", signal.SIGKILL, (3 * total) // 4, 2, 1)]:
        out = fresh(label)
        run(case_args(out), t1, (sig, step))
        code, err = run(["--restart", str(out)], t2)
        if code != 0:
            failures.append(f"{label}: restart failed ({code}): {err.strip()}")
            continue
        compare(ref, out, label)

code, err = run(["--restart", str(work / "no_such_run")], 1)
if code != 2 or "no checkpoint" not in err:
    failures.append(f"restart of a folder without checkpoints: exit {code}, '{err.strip()}'")

for f in failures:
    print("FAIL", f)
sys.exit(1 if failures else 0)
