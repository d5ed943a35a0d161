#!/usr/bin/python3
"""The command line (issue 24): argument errors exit with status 2 and say what is wrong, a case
path that is not a regular file is refused at once, a --set value that is not TOML is said to be
so, a top-level --set key that belongs to a section is pointed to it, and talus check estimates
the output (frames, bytes) and warns of a case that would write too many frames or more than
the free disk.

Usage: command_line_test.py TALUS SOURCE_DIR WORK_DIR
"""
import json
import shutil
import subprocess
import sys
from pathlib import Path

talus, source, work = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
case = str(source / "cases/examples/block_on_floor.toml")
failures = []
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)


def expect(args, code, text):
    p = subprocess.run([talus, *args], capture_output=True, text=True, timeout=30)
    out = p.stdout + p.stderr
    ok = p.returncode == code and text in out
    print(("ok   " if ok else "FAIL ") + f"talus {' '.join(args)}: exit {p.returncode}: "
          f"{out.strip().splitlines()[-1] if out.strip() else ''}")
    if not ok:
        failures.append(args)


expect([], 2, "subcommand")
expect(["run", case, "--no-such-option"], 2, "--no-such-option")
expect(["run", case, "--threads", "0"], 2, "--threads")
expect(["run", case, "--threads", "10000"], 2, "--threads")
expect(["--help"], 0, "Usage")
expect(["check", "/dev/zero"], 2, "not a regular file")
# bench and verify: a bad option is a clear error (exit 2) before anything runs, never an abort.
expect(["bench", "--threads", "0"], 2, "--threads")
expect(["bench", "--problems", "colum"], 2, "--problems")
expect(["bench", "--problems", "column,nosuch"], 2, "--problems")
expect(["bench", "--json", str(work)], 2, "is a folder")
expect(["bench", "--json", str(work / "no_such_folder/x.json")], 2, "does not exist")
expect(["verify", "--cases", "nosuch", "--out", str(work / "report")], 2, "no case named nosuch")
(work / "a_file").write_text("x\n")
expect(["verify", "--out", str(work / "a_file")], 2, "cannot make the report folder")
expect(["check", case, "--set", "simulation.gravity=[0,"], 2, "does not parse as TOML")
expect(["check", case, "--set", "body.block.velocity=[1e999,0]"], 2, "does not parse as TOML")
expect(["check", case, "--set", "end_time=1"], 2, "did you mean simulation.end_time?")
expect(["check", case, "--set", "grid..cell_size=1"], 2, "--set 'grid..cell_size': a key path")
expect(["check", case, "--set", ".grid=1"], 2, "--set '.grid': a key path with an empty part")
expect(["check", case, "--set", "simulation.scheme=usf"], 0, "particles")  # a bare word: string
expect(["verify", "--threads", "-1", "--out", str(work / "report")], 2, "--threads")
expect(["verify", "--cases", "--out", str(work / "report")], 2, "--cases")
expect(["verify", "--jobs", "0", "--out", str(work / "report")], 2, "--jobs")
expect(["verify", "--also-shape", "quadratic", "--out", str(work / "report")], 2, "--also-shape")
expect(["verify", "--also-set", "simulation.xpic", "--out", str(work / "report")], 2, "--also-set")
expect(["verify", "--also-shape", "bspline", "--also-set", "simulation.xpic=2", "--out",
        str(work / "report")], 2, "--also-set")
expect(["check", case, "--set", "grid.shape_function=spline"], 2, "shape_function")
# verify --threads is a cap: a case of a few thousand particles runs on one thread, as a plain
# `talus run` picks (one per 25,000 particles), not on the two asked for.
p = subprocess.run([talus, "verify", "--cases", "self_weight_column", "--threads", "2", "--source",
                    str(source), "--out", str(work / "capped")], capture_output=True, text=True,
                   timeout=300)
used = sorted({json.loads(s.read_text())["threads"]
               for s in (work / "capped" / "runs").glob("*/summary.json")})
ok = p.returncode == 0 and used == [1]
print(("ok   " if ok else "FAIL ") + f"verify --threads 2 on self_weight_column: exit {p.returncode}, "
      f"threads per run {used}")
if not ok:
    failures.append("verify --threads cap")
# verify --jobs 2 runs two at once and reports the same table as one at a time.
tables = []
for jobs in ("1", "2"):
    folder = work / f"jobs{jobs}"
    p = subprocess.run([talus, "verify", "--cases", "self_weight_column", "cohesive_slope", "--jobs",
                        jobs, "--source", str(source), "--out", str(folder)],
                       capture_output=True, text=True, timeout=600)
    tables.append([line for line in (folder / "report.md").read_text().splitlines()
                   if line.startswith("| self_weight_column") or line.startswith("| cohesive_slope")]
                  if p.returncode == 0 else None)
ok = tables[0] is not None and len(tables[0]) > 0 and tables[0] == tables[1]
print(f"ok   verify --jobs 2: {len(tables[0])} rows, the same as --jobs 1" if ok
      else "FAIL verify --jobs 2: the tables differ, or a run failed")
if not ok:
    failures.append("verify --jobs")
# A terminal escape in a --set value is not echoed raw by its error.
p = subprocess.run([talus, "check", case, "--set", "title=\x1b[31mred\x1b[0m"],
                   capture_output=True, text=True, timeout=30)
ok = p.returncode == 2 and "--set title" in p.stderr and "\x1b" not in p.stderr + p.stdout
print(("ok   " if ok else "FAIL ") + f"an escape in a --set value is not echoed (exit {p.returncode})")
if not ok:
    failures.append("escape echoed")
# A closed stdout (talus run ... | head -c 1) loses the log, not the run: it ends stopped, not
# killed by SIGPIPE with its summary left at "running".
piped = subprocess.Popen([talus, "run", case, "--out", str(work / "piped"), "--max-steps", "50"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE)
piped.stdout.read(1)
piped.stdout.close()
piped.wait(timeout=120)
summary = json.loads((work / "piped" / "summary.json").read_text())
ok = piped.returncode == 0 and summary["status"] == "stopped"
print(("ok   " if ok else "FAIL ") + f"a closed stdout: exit {piped.returncode}, {summary['status']}")
if not ok:
    failures.append("closed stdout")
# A probe far from its body is warned of (talus run prints the set-up's warnings).
p = subprocess.run([talus, "run", case, "--out", str(work / "probe"), "--max-steps", "1", "--set",
                    "probe.block_top.near=[0.3, 1.9]"], capture_output=True, text=True, timeout=60)
ok = p.returncode == 0 and "probe 'block_top'" in p.stdout and "more than a cell" in p.stdout
print(("ok   " if ok else "FAIL ") + "a probe far from its body is warned of")
if not ok:
    failures.append("probe warning")

# talus check estimates the output and warns of a case that would write too much.
expect(["check", case], 0, "output about 21 frames")  # 1 s at 0.05 s, and t = 0
expect(["check", case, "--set", "output.every=0.0000999"], 0, "more than 10,000")
expect(["check", case, "--set", "output.every=1e-9"], 2, "does not fit")
expect(["check", case, "--set", "output.every=1e-9"], 2, "more than 10,000")
# talus run says check's warnings again, and refuses what check refuses, before writing anything.
expect(["run", case, "--out", str(work / "full"), "--set", "output.every=1e-9"], 2, "does not fit")
expect(["run", case, "--out", str(work / "many"), "--set", "output.every=0.0001", "--max-steps",
        "1"], 0, "warning: output.every")
ok = not (work / "full").exists()
print(("ok   " if ok else "FAIL ") + "a refused run writes no folder")
if not ok:
    failures.append("refused run folder")
# Numbers out of any physical range: refused by check and run, or a run that stops at once.
for key, text in [("simulation.end_time=1e300", "more than the 1e+09"),
                  ("material.rubber.youngs_modulus=1e300", "more than the 1e+09"),
                  ("material.rubber.density=1e300", "between 1 and 100,000"),
                  ("material.rubber.density=1e-300", "between 1 and 100,000")]:
    expect(["check", case, "--set", key], 2, text)
    expect(["run", case, "--out", str(work / "absurd"), "--set", key], 2, text)
expect(["run", case, "--out", str(work / "fast"), "--set", "body.block.velocity=[1e10, 0]"], 1,
       "more than the 1e+09 a run may take")
expect(["run", case, "--out", str(work / "overflow"), "--set", "body.block.velocity=[1e155, 0]"],
       1, "not finite")

# The real-DEM example (cases/examples/volcano_slide.toml): the slide's particles hold the volume
# between its two rasters' bilinear surfaces inside the footprint (integrated here on a 0.5 m
# grid), within the lattice's sampling error (2 %).
import re  # noqa: E402

import numpy as np  # noqa: E402

vdir = source / "cases/examples/volcano"
p = subprocess.run([talus, "check", str(source / "cases/examples/volcano_slide.toml")],
                   capture_output=True, text=True, timeout=60)
m = re.search(r"body slide\s+(\d+) particles", p.stdout)
top = np.loadtxt(vdir / "maunga_whau.asc", skiprows=6)[::-1]
bottom = np.loadtxt(vdir / "failure_surface.asc", skiprows=6)[::-1]
ring = np.loadtxt(vdir / "slide_footprint.csv", delimiter=",", skiprows=1)


def bilinear(d, x, y):  # 10 m cells from (0, 0), values at the centres, held over the last half cell
    i = np.clip((x - 5.0) / 10.0, 0, d.shape[1] - 1.000001)
    j = np.clip((y - 5.0) / 10.0, 0, d.shape[0] - 1.000001)
    i0, j0 = np.floor(i).astype(int), np.floor(j).astype(int)
    fx, fy = i - i0, j - j0
    return (d[j0, i0] * (1 - fx) * (1 - fy) + d[j0, i0 + 1] * fx * (1 - fy)
            + d[j0 + 1, i0] * (1 - fx) * fy + d[j0 + 1, i0 + 1] * fx * fy)


h = 0.5
X, Y = np.meshgrid(np.arange(ring[:, 0].min(), ring[:, 0].max(), h) + h / 2,
                   np.arange(ring[:, 1].min(), ring[:, 1].max(), h) + h / 2)
inside = np.zeros(X.shape, bool)  # even-odd rule over the footprint's edges
for (x0, y0), (x1, y1) in zip(ring, np.roll(ring, -1, axis=0)):
    crosses = (y0 > Y) != (y1 > Y)
    inside ^= crosses & (X < x0 + (Y - y0) * (x1 - x0) / np.where(y1 != y0, y1 - y0, 1.0))
exact = ((bilinear(top, X, Y) - bilinear(bottom, X, Y)) * inside).sum() * h * h
seeded = int(m.group(1)) * 2.5 ** 3 if m else 0.0
ok = p.returncode == 0 and abs(seeded / exact - 1.0) < 0.02
print(("ok   " if ok else "FAIL ") + f"volcano slide: {seeded:.0f} m^3 seeded, {exact:.0f} m^3 "
      "between the rasters")
if not ok:
    failures.append("volcano volume")

print(f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
