#!/usr/bin/env python3
"""Instructions and L1 data-cache misses per particle update, phase by phase, under callgrind.

Runs `talus bench --threads 1 --problems PROBLEM` under valgrind's callgrind (with its cache
simulation), sums the inclusive costs of the step's functions by the phase whose timer runs them
(Simulation::step: p2g, grid, contact, g2p, stress, other) and divides by the bench's particle
updates (particles x steps). The set-up's cost is outside the step and left out. The run is
about 150 times slower than the bench itself (the 2D Vaiont: about 20 minutes).

Usage: tools/phase_instructions.py [--talus build/release/talus] [--out DIR] PROBLEM [PROBLEM ...]
Prints a Markdown table: instructions and D1 misses per update for each phase and the step.
"""
import argparse
import os
import re
import subprocess
import sys
from pathlib import Path

# The functions each phase's timer runs (solver/simulation.cpp, Simulation::step).
PHASES = {
    "p2g": ["map_particles_to_nodes", "map_forces_to_nodes"],
    "grid": ["compute_node_velocities", "apply_velocity_conditions", "integrate_node_forces",
             "hold_hydrostatic_load"],
    "contact": ["share_interface_loads", "apply_contact"],
    "g2p": ["update_particles_and_remap", "update_particles", "extrapolate_xpic_velocity"],
    "stress": ["update_stress"],
    "other": ["begin_step", "update_interface_history", "update_orphans"],
}


def inclusive_costs(out_file):
    """{function name: (Ir, D1 misses)}: the largest inclusive cost of Simulation<D>::NAME(
    (its OpenMP clones and lambdas are inside it)."""
    text = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100",
                           str(out_file)], capture_output=True, text=True, check=True).stdout
    costs = {}
    for line in text.splitlines():
        m = re.search(r"Simulation<\d>::([a-z_0-9]+)\(", line)
        at = line.find("???:")
        if not m or at < 0 or "{lambda" in line[:m.start()]:
            continue
        # The event columns: counts, each with its share in parentheses, or "." for none.
        counts = [0 if t == "." else int(t.replace(",", ""))
                  for t in re.sub(r"\([^)]*\)", " ", line[:at]).split()]
        ir = counts[0]
        d1 = counts[4] + counts[5] if len(counts) >= 6 else 0  # D1mr + D1mw
        if ir > costs.get(m.group(1), (0, 0))[0]:
            costs[m.group(1)] = (ir, d1)
    return costs


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("problems", nargs="+")
    ap.add_argument("--talus", default="build/release/talus")
    ap.add_argument("--out", default="/tmp/talus_callgrind")
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, OMP_WAIT_POLICY="passive")  # no re-execution (share_cores)
    print("| problem | phase | instructions per update | D1 misses per update |")
    print("|---|---|---|---|")
    for problem in a.problems:
        data = out / f"{problem}.callgrind"
        run = subprocess.run(["valgrind", "--tool=callgrind", "--cache-sim=yes",
                              f"--callgrind-out-file={data}", a.talus, "bench", "--threads", "1",
                              "--problems", problem], capture_output=True, text=True, env=env)
        row = next((line.split() for line in run.stdout.splitlines()
                    if line.startswith(problem + " ")), None)
        if run.returncode != 0 or row is None:
            sys.exit(f"{problem}: the bench under callgrind failed:\n{run.stderr[-2000:]}")
        updates = int(row[2]) * int(row[3])  # particles x steps
        costs = inclusive_costs(data)
        total_ir = total_d1 = 0
        for phase, names in PHASES.items():
            ir = sum(costs.get(n, (0, 0))[0] for n in names)
            d1 = sum(costs.get(n, (0, 0))[1] for n in names)
            total_ir, total_d1 = total_ir + ir, total_d1 + d1
            print(f"| {problem} | {phase} | {ir / updates:.0f} | {d1 / updates:.1f} |")
        step = costs.get("step", (total_ir, total_d1))
        print(f"| {problem} | the step | {step[0] / updates:.0f} | {step[1] / updates:.1f} |")


if __name__ == "__main__":
    main()
