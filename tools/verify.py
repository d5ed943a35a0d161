#!/usr/bin/env python3
"""The verification suite and its report: `talus verify [--quick | --full] [--out DIR]`.

Runs every case in cases/benchmarks/ and the Vaiont three-body case with the overrides of its
[verify] table (quick: CI resolution; full: the paper's), evaluates each [[check]] of the case
file against the run folder, and writes DIR/report.md and DIR/report.html: one table row per
check (measured, reference, error, tolerance, source, status) and the plots beside each case.
The tolerances and references live in the case files, next to the closed form they come from;
this script only measures and reports. docs/case-file.md documents [[check]].

Quantities (QUANTITY at TIME, read from the run folder):
  body.NAME.displacement[_x|_y|_z]   centroid displacement since the first output row
                                     (with `direction`: its component along that vector)
  body.NAME.COLUMN                   a column of bodies.csv (mean_speed, velocity_x, ...)
  probe.NAME.displacement[_x|_y|_z]  a probe's displacement since the first row (or direction)
  probe.NAME.COLUMN                  a column of probes.csv (speed, x, y, ...)
  interface.A-B.COLUMN_mean          time mean of interfaces.csv (cohesive_force,
                                     frictional_force, normal_force, tangential_force) to TIME
  energy.COLUMN                      a column of energy.csv
  particle.FIELD                     a VTU field (stress_xx .. stress_xz, velocity_x,
                                     displacement_y, ...) of the particle nearest `near`
  extent.BODY.x_max (x_min, y_max..) the extreme particle position of a body
  results.KEY[.KEY]                  summary.json's results
Exit status: 0 when every check passes or is a documented known miss, 1 otherwise.
"""
import argparse
import csv
import html
import json
import math
import os
import re
import subprocess
import sys
import time
import tomllib
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import talus_frames  # noqa: E402


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def at_time(rows, t, what):
    best = min(rows, key=lambda r: abs(float(r["time"]) - t))
    if abs(float(best["time"]) - t) > 1e-6 * max(1.0, abs(t)):
        raise ValueError(f"{what}: no output row at t = {t} (nearest {best['time']}); "
                         "set output.every to land on it")
    return best


class Run:
    def __init__(self, folder):
        self.dir = Path(folder)
        self.cache = {}

    def table(self, name):
        if name not in self.cache:
            self.cache[name] = read_csv(self.dir / name)
        return self.cache[name]

    def summary(self):
        return json.loads((self.dir / "summary.json").read_text())

    def series(self, check):
        """(times, values) of a check's quantity over the run, or None if it has no series."""
        parts = check["quantity"].split(".")
        kind = parts[0]
        if kind in ("body", "probe"):
            rows = [r for r in self.table("bodies.csv" if kind == "body" else "probes.csv")
                    if r["body" if kind == "body" else "probe"] == parts[1]]
            if not rows:
                raise ValueError(f"{check['quantity']}: no {kind} named '{parts[1]}'")
            t = np.array([float(r["time"]) for r in rows])
            col = parts[2]
            prefix = "centroid_" if kind == "body" else ""
            if col.startswith("displacement") and (kind == "body" or col != "displacement"
                                                   or "direction" in check):
                axes = [a for a in "xyz" if f"{prefix}{a}" in rows[0]]
                x = np.array([[float(r[f"{prefix}{a}"]) for a in axes] for r in rows])
                d = x - x[0]
                if "direction" in check:
                    n = np.array(check["direction"], dtype=float)
                    return t, d @ (n / np.linalg.norm(n))
                if col == "displacement":
                    return t, np.linalg.norm(d, axis=1)
                return t, d[:, axes.index(col[-1])]
            return t, np.array([float(r[col]) for r in rows])
        if kind == "energy":
            rows = self.table("energy.csv")
            return (np.array([float(r["time"]) for r in rows]),
                    np.array([float(r[parts[1]]) for r in rows]))
        if kind == "interface":
            rows = [r for r in self.table("interfaces.csv") if r["interface"] == parts[1]]
            col = parts[2].removesuffix("_mean")
            t = np.array([float(r["time"]) for r in rows])
            if col == "tangential_force":
                v = np.array([float(r["cohesive_force"]) + float(r["frictional_force"])
                              for r in rows])
            else:
                v = np.array([float(r[col]) for r in rows])
            return t, v
        return None

    def value(self, check):
        q = check["quantity"]
        parts = q.split(".")
        t = check.get("time")
        if parts[0] == "results":
            v = self.summary()["results"]
            for p in parts[1:]:
                v = v[p]
            if v is None:
                raise ValueError(f"{q} is null in summary.json")
            return float(v)
        if parts[0] == "particle":
            return self.particle_value(check)
        if parts[0] == "extent":
            return self.extent_value(check)
        ts, vs = self.series(check)
        if parts[0] == "interface":
            sel = (ts > 0) & (ts <= (t if t is not None else ts[-1]) + 1e-9)
            return float(vs[sel].mean())
        if t is None:
            raise ValueError(f"{q}: give the check a time")
        i = int(np.argmin(abs(ts - t)))
        if abs(ts[i] - t) > 1e-6 * max(1.0, t):
            raise ValueError(f"{q}: no output at t = {t} (nearest {ts[i]})")
        return float(vs[i])

    def frame(self, t):
        tf, files = min(talus_frames.times(self.dir), key=lambda fr: abs(fr[0] - t))
        if abs(tf - t) > 1e-6 * max(1.0, t):
            raise ValueError(f"no particle frame at t = {t} (nearest {tf})")
        return talus_frames.read(self.dir, files)

    def extent_value(self, check):
        """extent.BODY.x_max (y_min, ...): the extreme particle position of a body."""
        _, body, which = check["quantity"].split(".")
        names = self.summary()["bodies"]
        index = list(names).index(body)
        m = self.frame(check["time"])
        x = m.points[m.point_data["body"].ravel().astype(int) == index]
        axis = "xyz".index(which[0])
        return float(x[:, axis].max() if which.endswith("max") else x[:, axis].min())

    def particle_value(self, check):
        frames = talus_frames.times(self.dir)
        t = check.get("time", frames[-1][0])
        tf, m = talus_frames.nearest(self.dir, t, frames)
        field = check["quantity"].split(".")[1]
        name, _, comp = field.rpartition("_")
        comps = {"stress": ["xx", "yy", "zz", "xy", "yz", "xz"], "velocity": ["x", "y", "z"],
                 "displacement": ["x", "y", "z"]}
        data = m.point_data[name]
        col = comps[name].index(comp)
        near = np.array(check["near"], dtype=float)
        i = int(np.argmin(np.linalg.norm(m.points[:, :len(near)] - near, axis=1)))
        return float(data[i, col])


def evaluate(check, run):
    row = {"name": check["name"], "quantity": check["quantity"], "source": check["source"],
           "time": check.get("time"), "known_miss": check.get("known_miss", "")}
    try:
        v = run.value(check)
    except (ValueError, KeyError, IndexError, FileNotFoundError) as e:
        row.update(measured=None, status="ERROR", error=str(e), reference="", tolerance="")
        return row
    row["measured"] = v
    if "reference" in check:
        ref = check["reference"]
        if "tolerance" in check:
            err = (v - ref) / abs(ref) if ref != 0 else math.inf
            ok = abs(err) <= check["tolerance"]
            row.update(reference=ref, error=f"{100 * err:+.3g} %",
                       tolerance=f"{100 * check['tolerance']:.3g} %")
        else:
            err = v - ref
            ok = abs(err) <= check["abs_tolerance"]
            row.update(reference=ref, error=f"{err:+.3g}", tolerance=f"{check['abs_tolerance']:.3g}")
    else:
        lo, hi = check.get("min", -math.inf), check.get("max", math.inf)
        ok = lo <= v <= hi
        row.update(reference=f"[{lo:.4g}, {hi:.4g}]", error="", tolerance="bounds")
    if ok:
        row["status"] = "pass"
    else:
        row["status"] = "known miss" if row["known_miss"] else "FAIL"
    return row


def plot(case_name, label, run, checks, path):
    series = []
    for c in checks:
        try:
            s = run.series(c)
        except (ValueError, KeyError):
            s = None
        if s is not None:
            series.append((c, s))
    if not series:
        return None
    # One panel per distinct quantity.
    quantities = []
    for c, s in series:
        key = (c["quantity"], tuple(c.get("direction", [])))
        if key not in [k for k, _ in quantities]:
            quantities.append((key, (c, s)))
    fig, axes = plt.subplots(1, len(quantities), figsize=(5.0 * len(quantities), 3.6),
                             squeeze=False)
    for ax, (q, (c0, (t, v))) in zip(axes[0], quantities):
        ax.plot(t, v, "-", color="#1f77b4", label="Talus")
        for c, _ in series:
            if (c["quantity"], tuple(c.get("direction", []))) != q or c.get("time") is None:
                continue
            if "reference" in c:
                ax.plot([c["time"]], [c["reference"]], "x", color="#d62728", ms=9, mew=2)
            else:
                lo, hi = c.get("min", np.nan), c.get("max", np.nan)
                ax.errorbar([c["time"]], [np.nanmean([lo, hi])], fmt="none", ecolor="#d62728",
                            yerr=[[np.nanmean([lo, hi]) - lo], [hi - np.nanmean([lo, hi])]])
        ax.plot([], [], "x", color="#d62728", ms=9, mew=2, label="reference (x) or bounds (bar)")
        ax.set_xlabel("time (s)")
        ax.set_ylabel(q[0] + (" along " + str(list(q[1])) if q[1] else ""))
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    fig.suptitle(f"{case_name} {label}".strip())
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def talus_run(a, case, folder, overrides):
    """`talus run` of the case into folder with the overrides (--overwrite: talus empties its
    own earlier run folder, and refuses any other). --threads is a cap, not a count: the run
    takes one thread per 25,000 particles up to the threads it starts with (OMP_NUM_THREADS), as
    a plain `talus run` does; a small case on two threads waits more than it works."""
    cmd = [a.talus, "run", str(case), "--out", str(folder), "--overwrite"]
    for s in overrides:
        cmd += ["--set", s]
    env = None
    cap = run_thread_cap(a)
    if cap:
        env = dict(os.environ, OMP_NUM_THREADS=str(cap))
    return subprocess.run(cmd, capture_output=True, text=True, stdin=subprocess.DEVNULL, env=env)


def run_thread_cap(a):
    """The most threads a run may take (0: no cap): --threads, and with --jobs N the cores over N,
    so that N runs at once do not share a core."""
    caps = [a.threads] if a.threads else []
    if a.jobs > 1:
        caps.append(max(1, (os.cpu_count() or 1) // a.jobs))
    return min(caps) if caps else 0


def usage_error(message):
    """A bad command line: one line on stderr, exit status 2 (as talus's own errors)."""
    print(f"error: verify: {message}", file=sys.stderr)
    sys.exit(2)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--talus", required=True)
    ap.add_argument("--source", default=".")
    mode = ap.add_mutually_exclusive_group()
    mode.add_argument("--quick", action="store_true", help="CI resolution (default)")
    mode.add_argument("--full", action="store_true", help="the paper's resolution")
    ap.add_argument("--out", default="verification")
    ap.add_argument("--cases", nargs="*", help="only these case names (file stems)")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--update-docs", action="store_true",
                    help="write the table into docs/verification.md (between its markers)")
    also = ap.add_mutually_exclusive_group()
    also.add_argument("--also-shape", choices=["linear", "gimp", "bspline"],
                      help="run every check again with this shape function (a column of the "
                           "report; its misses do not fail the suite)")
    also.add_argument("--also-set", metavar="KEY=VALUE",
                      help="run every check again with this key overridden (a column of the "
                           "report, as --also-shape), e.g. simulation.xpic=2")
    a = ap.parse_args()
    if a.jobs < 1:
        usage_error(f"--jobs {a.jobs}: needs at least 1")
    if a.threads < 0:
        usage_error(f"--threads {a.threads}: needs at least 1")
    if a.also_set is not None and ("=" not in a.also_set or a.also_set.startswith("=")):
        usage_error(f"--also-set {a.also_set}: needs KEY=VALUE")
    # The second column's override and its label (--also-shape X is grid.shape_function="X").
    alt_set = (f'grid.shape_function="{a.also_shape}"' if a.also_shape else a.also_set)
    alt_label = a.also_shape or a.also_set
    level = "full" if a.full else "quick"
    src = Path(a.source).resolve()
    out = Path(a.out)
    cases = sorted((src / "cases/benchmarks").glob("*.toml")) + [
        src / "cases/vaiont/three_bodies.toml"]
    if a.cases:
        unknown = sorted(set(a.cases) - {c.stem for c in cases})
        if unknown:
            usage_error(f"no case named {', '.join(unknown)}; the cases are "
                        f"{', '.join(c.stem for c in cases)}")
        cases = [c for c in cases if c.stem in a.cases]
    try:
        out.mkdir(parents=True, exist_ok=True)
        (out / "img").mkdir(exist_ok=True)
    except OSError as e:
        usage_error(f"--out {out}: cannot make the report folder: {e.strerror}")
    rows, sections, started = [], [], time.time()

    def timed_run(case, folder, overrides):
        t0 = time.time()
        p = talus_run(a, case, folder, overrides)
        return p, time.time() - t0

    # Every run is handed to the pool up front (--jobs of them at once) and read back in the
    # suite's order, so the report is the same whatever the number of jobs.
    pool = ThreadPoolExecutor(max_workers=a.jobs)
    plan = []
    for case in cases:
        doc = tomllib.loads(case.read_text())
        checks = doc.get("check", [])
        if not checks:
            continue
        base = doc.get("verify", {}).get(level, [])
        groups = {}
        for c in checks:
            groups.setdefault(tuple(c.get("set", [])), []).append(c)
        runs = []
        for k, (sets, group) in enumerate(groups.items()):
            folder = out / "runs" / (case.stem + (f"_{k}" if len(groups) > 1 else ""))
            overrides = list(base) + list(sets)
            main_run = pool.submit(timed_run, case, folder, overrides)
            alt_folder = alt_run = None
            if alt_set:  # the same run with the second column's override, beside it
                alt_folder = out / "runs" / (folder.name + "_" +
                                             re.sub(r"[^A-Za-z0-9]+", "_", alt_label))
                alt_run = pool.submit(timed_run, case, alt_folder, overrides + [alt_set])
            runs.append((sets, group, folder, main_run, alt_folder, alt_run))
        plan.append((case, doc, base, runs))
    for case, doc, base, runs in plan:
        section = {"case": case.stem, "title": doc.get("title", ""), "plots": [], "runs": []}
        for sets, group, folder, main_run, alt_folder, alt_run in runs:
            label = ", ".join(sets)
            p, wall = main_run.result()
            print(f"{case.stem} {label}: exit {p.returncode}, {wall:.1f} s", flush=True)
            section["runs"].append({"overrides": list(base) + list(sets), "wall": wall,
                                    "exit": p.returncode})
            alt, alt_failure = None, ""
            if alt_run:
                q, _ = alt_run.result()
                print(f"{case.stem} {label} ({alt_label}): exit {q.returncode}", flush=True)
                if q.returncode == 0:
                    alt = Run(alt_folder)
                elif q.returncode == 2:  # the case refuses the override (e.g. xpic under apic)
                    alt_failure = f"not run: {q.stderr.strip().splitlines()[-1:]}"
                else:
                    alt_failure = f"run failed: {q.stderr.strip().splitlines()[-1:]}"
            run = Run(folder)
            for c in group:
                if p.returncode != 0:
                    r = {"name": c["name"], "quantity": c["quantity"], "source": c["source"],
                         "time": c.get("time"), "known_miss": c.get("known_miss", ""),
                         "measured": None, "reference": c.get("reference", ""), "error":
                         f"run failed: {p.stderr.strip().splitlines()[-1:]}",
                         "tolerance": "", "status": "ERROR"}
                else:
                    r = evaluate(c, run)
                r["case"] = case.stem
                r["plot"] = None
                if alt_set:
                    s = evaluate(c, alt) if alt else {
                        "measured": None, "error": alt_failure,
                        "status": "n/a" if alt_failure.startswith("not run") else "ERROR"}
                    r["alt"] = {"label": alt_label, "measured": s["measured"],
                                "error": s["error"], "status": s["status"]}
                rows.append(r)
                print(f"  {r['status']:>10}  {c['name']}: {r['measured']} (reference "
                      f"{r['reference']}, {r['error']})", flush=True)
            if p.returncode == 0:
                png = plot(case.stem, label, run, group,
                           out / "img" / f"{folder.name}.png")
                if png:
                    section["plots"].append(f"img/{folder.name}.png")
                    for r in rows[-len(group):]:
                        r["plot"] = f"img/{folder.name}.png"
        sections.append(section)
    pool.shutdown()
    elapsed = time.time() - started
    write_reports(out, rows, sections, level, elapsed)
    if a.update_docs:
        update_docs(src / "docs/verification.md", rows, level)
    failed = [r for r in rows if r["status"] in ("FAIL", "ERROR")]
    misses = [r for r in rows if r["status"] == "known miss"]
    print(f"{len(rows)} checks: {len(rows) - len(failed) - len(misses)} pass, {len(misses)} "
          f"known misses, {len(failed)} fail; {elapsed:.0f} s; report {out / 'report.html'}")
    return 1 if failed else 0


def fmt(v):
    if v is None or v == "":
        return ""
    if isinstance(v, float):
        return f"{v:.6g}"
    return str(v)


def table_md(rows):
    alt = next((r["alt"]["label"] for r in rows if "alt" in r), None)
    extra = f" {alt}: measured | {alt}: error | {alt}: status |" if alt else ""
    lines = ["| case | check | t (s) | measured | reference | error | tolerance | status | "
             "source |" + extra, "|---|---|---|---|---|---|---|---|---|" +
             ("---|---|---|" if alt else "")]
    for r in rows:
        status = r["status"] + (f" ({r['known_miss']})" if r["status"] == "known miss" else "")
        cells = [r["case"], r["name"], fmt(r["time"]), fmt(r["measured"]), fmt(r["reference"]),
                 r["error"], r["tolerance"], status, r["source"]]
        if alt:
            s = r.get("alt", {})
            cells += [fmt(s.get("measured")), s.get("error", ""), s.get("status", "")]
        lines.append("| " + " | ".join(cells).replace("\n", " ") + " |")
    return "\n".join(lines)


def write_reports(out, rows, sections, level, elapsed):
    n_pass = sum(r["status"] == "pass" for r in rows)
    head = (f"Talus verification ({level}): {len(rows)} checks, {n_pass} pass, "
            f"{sum(r['status'] == 'known miss' for r in rows)} known misses, "
            f"{sum(r['status'] in ('FAIL', 'ERROR') for r in rows)} fail; {elapsed:.0f} s")
    alts = [r["alt"] for r in rows if "alt" in r]
    if alts:
        head += (f"; with {alts[0]['label']}: "
                 f"{sum(s['status'] == 'pass' for s in alts)} pass, "
                 f"{sum(s['status'] == 'known miss' for s in alts)} known misses, "
                 f"{sum(s['status'] in ('FAIL', 'ERROR') for s in alts)} fail")
    md = [f"# {head}", "", table_md(rows), ""]
    for s in sections:
        md.append(f"## {s['case']}: {s['title']}")
        for run in s["runs"]:
            md.append(f"- run `{' '.join(run['overrides']) or '(case as is)'}`: "
                      f"{run['wall']:.1f} s, exit {run['exit']}")
        md += [f"![{s['case']}]({p})" for p in s["plots"]] + [""]
    (out / "report.md.tmp").write_text("\n".join(md) + "\n")
    (out / "report.md.tmp").replace(out / "report.md")

    colour = {"pass": "#e6f4ea", "known miss": "#fff4ce", "FAIL": "#fde7e9", "ERROR": "#fde7e9"}
    trs = []
    for r in rows:
        cells = [r["case"], r["name"], fmt(r["time"]), fmt(r["measured"]), fmt(r["reference"]),
                 r["error"], r["tolerance"],
                 r["status"] + (f": {r['known_miss']}" if r["known_miss"] else ""), r["source"]]
        if "alt" in r:
            cells += [fmt(r["alt"]["measured"]), r["alt"]["error"], r["alt"]["status"]]
        trs.append(f'<tr class="check" style="background:{colour[r["status"]]}">' +
                   "".join(f"<td>{html.escape(c)}</td>" for c in cells) + "</tr>")
    body = [f"<h1>{html.escape(head)}</h1>",
            '<table id="checks"><thead><tr><th>case</th><th>check</th><th>t (s)</th>'
            "<th>measured</th><th>reference</th><th>error</th><th>tolerance</th><th>status</th>"
            "<th>source</th>" + "".join(f"<th>{html.escape(alts[0]['label'])}: {h}</th>"
                                        for h in ("measured", "error", "status") if alts) +
            "</tr></thead><tbody>", *trs, "</tbody></table>"]
    for s in sections:
        body.append(f"<h2>{html.escape(s['case'])}: {html.escape(s['title'])}</h2>")
        body += [f'<img src="{html.escape(p)}" alt="{html.escape(s["case"])}">'
                 for p in s["plots"]]
    # On load, the page reports in its title how many images decoded and how many check rows it
    # has: the headless-browser test reads it.
    script = """<script>
window.addEventListener('load', () => {
  const imgs = [...document.images];
  const ok = imgs.filter(i => i.complete && i.naturalWidth > 0).length;
  const rows = document.querySelectorAll('#checks tr.check').length;
  document.title = `verify: images ${ok}/${imgs.length}, rows ${rows}`;
});
</script>"""
    page = ("<!DOCTYPE html><html><head><meta charset='utf-8'><title>Talus verification</title>"
            "<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse;"
            "font-size:13px}td,th{border:1px solid #ccc;padding:3px 6px}img{max-width:100%;"
            "margin:4px 0}</style>" + script + "</head><body>" + "\n".join(body) +
            "</body></html>\n")
    (out / "report.html.tmp").write_text(page)
    (out / "report.html.tmp").replace(out / "report.html")


def update_docs(path, rows, level):
    text = path.read_text()
    begin, end = "<!-- verify:begin -->", "<!-- verify:end -->"
    block = (f"{begin}\nGenerated by `talus verify --{level} --update-docs` "
             f"({time.strftime('%Y-%m-%d')}); every number is the measured one.\n\n"
             f"{table_md(rows)}\n{end}")
    if begin in text:
        text = re.sub(re.escape(begin) + ".*?" + re.escape(end), lambda m: block, text,
                      flags=re.S)
    else:
        text = text.rstrip() + "\n\n## The verification table\n" + block + "\n"
    path.write_text(text)


if __name__ == "__main__":
    sys.exit(main())
