#!/usr/bin/env python3
"""Opens the verification report (talus verify) in headless Chromium: every image must load and
the table must have one row per [[check]] in the case files (counted here from the TOML, not
from the report), and a screenshot of the page is taken.

Usage: report_browser_test.py SOURCE_DIR REPORT_DIR
"""
import re
import subprocess
import sys
import tomllib
from pathlib import Path

source, report = Path(sys.argv[1]), Path(sys.argv[2])
cases = sorted((source / "cases/benchmarks").glob("*.toml")) + [
    source / "cases/vaiont/three_bodies.toml"]
expected = sum(len(tomllib.loads(c.read_text()).get("check", [])) for c in cases)
page = (report / "report.html").resolve()
browser = ["chromium", "--headless=new", "--no-sandbox", "--disable-gpu", "--hide-scrollbars"]
dom = subprocess.run(browser + ["--virtual-time-budget=10000", "--dump-dom", page.as_uri()],
                     capture_output=True, text=True, timeout=120).stdout
m = re.search(r"<title>verify: images (\d+)/(\d+), rows (\d+)</title>", dom)
failures = []
if not m:
    failures.append("the page's load script did not run (no 'verify:' title)")
else:
    ok, total, rows = map(int, m.groups())
    print(f"images {ok}/{total}, table rows {rows}, checks in the case files {expected}")
    if total == 0 or ok != total:
        failures.append(f"{total - ok} of {total} images did not load")
    if rows != expected:
        failures.append(f"{rows} table rows for {expected} checks")
shot = report / "screenshot.png"
shot.unlink(missing_ok=True)
subprocess.run(browser + ["--window-size=1400,2400", f"--screenshot={shot}", page.as_uri()],
               capture_output=True, timeout=120)
if not shot.exists() or shot.stat().st_size < 20000:
    failures.append("no screenshot (or a blank one)")
else:
    print(f"screenshot {shot} ({shot.stat().st_size} bytes)")
for f in failures:
    print("FAIL", f)
sys.exit(1 if failures else 0)
