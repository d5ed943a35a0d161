#!/usr/bin/env python3
"""Interleaved A/B comparison of two Talus binaries with `talus bench` (docs/performance.md).

Runs `A bench` and `B bench` alternately (A, B, B, A, A, B, ...: neither always goes first, so a
machine that slows down or speeds up during the rounds favours neither), then prints each
problem's median updates/s and phase seconds for both, and B's median over A's.

    tools/bench_ab.py /tmp/talus_before build/release/talus --problems vaiont,vaiont_3d \\
        --threads 2 --rounds 5
"""
import argparse
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

PHASES = ["p2g", "grid", "contact", "g2p", "stress", "other"]


def run(binary, problems, threads, source):
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "bench.json"
        cmd = [binary, "bench", "--problems", problems, "--threads", str(threads),
               "--source", source, "--json", str(out)]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        return json.loads(out.read_text())


def rows(report):
    """(problem, threads) -> the bench's row."""
    return {(r["problem"], r["threads"]): r for r in report}


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("a", help="the binary before")
    ap.add_argument("b", help="the binary after")
    ap.add_argument("--problems", default="column,vaiont")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--source", default=".", help="the Talus source folder (the cases)")
    args = ap.parse_args()

    got = {"A": [], "B": []}
    for r in range(args.rounds):
        order = ["A", "B"] if r % 2 == 0 else ["B", "A"]
        for who in order:
            binary = args.a if who == "A" else args.b
            got[who].append(rows(run(binary, args.problems, args.threads, args.source)))
        print(f"round {r + 1}/{args.rounds} done", file=sys.stderr)

    print(f"medians of {args.rounds} interleaved rounds, {args.threads} threads")
    print(f"{'problem':<24}{'':>3}{'updates/s':>12}" + "".join(f"{p:>9}" for p in PHASES))
    for key in got["A"][0]:
        med = {}
        for who in ("A", "B"):
            runs = [g[key] for g in got[who]]
            med[who] = {p: statistics.median(r["phase_seconds"][p] for r in runs) for p in PHASES}
            med[who]["updates_per_second"] = statistics.median(
                r["particle_updates_per_second"] for r in runs)
            print(f"{key[0]:<24}{who:>3}{med[who]['updates_per_second']:>12.4g}"
                  + "".join(f"{med[who][p]:>9.3f}" for p in PHASES))
        ratio = med["B"]["updates_per_second"] / med["A"]["updates_per_second"]
        print(f"{'':<24}{'B/A':>3}{ratio:>12.3f}")


if __name__ == "__main__":
    main()
