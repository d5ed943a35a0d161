#!/usr/bin/env python3
"""The layout's direction: a library that includes a header of a library above it does not build.

Usage: check_layout.py BUILD_DIR PROBE...  where each PROBE is TARGET:HEADER:EXPECT and EXPECT is
`builds` or `fails`. A probe that must fail must fail because HEADER is not found (not for any
other reason); the controls that must build show the probes compile at all.
"""
import subprocess
import sys

build, probes = sys.argv[1], sys.argv[2:]
bad = 0
for probe in probes:
    target, header, expect = probe.split(":")
    r = subprocess.run(["cmake", "--build", build, "--target", target],
                       capture_output=True, text=True)
    out = r.stdout + r.stderr
    if expect == "builds":
        ok = r.returncode == 0
        why = "builds" if ok else "does not build:\n" + out[-2000:]
    else:
        not_found = f"{header}: No such file or directory" in out
        ok = r.returncode != 0 and not_found
        why = ("fails: the header is not found" if ok else
               "builds, though it includes a library above it" if r.returncode == 0 else
               "fails for another reason:\n" + out[-2000:])
    print(f"{'ok  ' if ok else 'FAIL'} {target} ({header}): {why}")
    bad += not ok
sys.exit(1 if bad else 0)
