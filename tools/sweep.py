#!/usr/bin/env python3
"""An ensemble of runs of one case (`talus sweep CASE`, which validates the case's [sweep] and
[observed] tables and starts this with their content as --plan).

1. The design: each parameter's values by Latin hypercube (`runs` runs; each parameter's range
   cut into `runs` strata of equal probability, one value drawn in each, the strata shuffled
   independently per parameter) or a grid (every combination of each parameter's levels), from
   Python's Mersenne Twister seeded with `seed`: the same design on any machine.
2. The runs: `talus run CASE --set KEY=VALUE ... --out SWEEP/run_NNN`, `--jobs` at a time, each
   with `--threads` threads (or under `--launcher`, e.g. mpirun). Resumable: a run whose
   summary.json says completed or failed is not run again; one that was interrupted continues
   from its newest checkpoint (`--restart`), one without a checkpoint starts again. Stopping the
   sweep (Ctrl-C, SIGTERM) stops its runs with a checkpoint each.
3. The table: SWEEP/table.csv, one row per run: its parameters, status and figures
   (summary.json `results`: run-out length, Fahrboschung angle, affected area, deposit volume,
   peak speed, ...).
4. Probability maps (3D with [maps]): the share of completed runs that reached each cell, and whose
   peak thickness, speed, kinetic energy or pressure exceeded each threshold of [sweep] exceed,
   as GeoTIFF in SWEEP/maps/ (with the ground and the release area of the first run, for the
   pictures); in 2D, maps/probability_profile.csv along the section.
5. Back-analysis ([observed]): each run scored against the observed impact outline (critical
   success index CSI = TP / (TP + FP + FN) over the map's cells, the share of the observed area
   reached TP / (TP + FN), the area reached but not observed, the run-out difference along the
   path), an observed deposit raster (its CSI above deposit_threshold, thickness RMSE) and
   observed figures (relative miss outside the observed range); SWEEP/ranking.csv ranks the runs.

Usage (through talus): talus sweep CASE.toml [--out DIR] [--jobs N] [--threads T] [--set K=V]
"""
import argparse
import fcntl
import hashlib
import json
import math
import os
import random
import signal
import subprocess
import sys
import time
from itertools import product
from pathlib import Path
from statistics import NormalDist

PLAN_FILE = "sweep.json"
# The figures tabled when the runs have them (summary.json `results`, key paths).
FIGURES = ["maps.runout_length_m", "maps.drop_height_m", "maps.fahrboschung_angle_deg",
           "maps.impact_area_m2", "maps.deposit_area_m2", "maps.release_volume_m3",
           "maps.deposit_volume_m3", "maps.peak_speed_m_s", "maps.impact_length_m",
           "maps.deposit_length_m", "peak_mean_speed_m_s", "peak_time_s",
           "centroid_displacement_x_m", "centroid_displacement_m", "runout_duration_s"]
MAP_FIELDS = {"peak_thickness": "m", "peak_speed": "m/s", "peak_kinetic_energy": "J/m^2",
              "peak_pressure": "Pa"}


def say(*args):
    """Prints a line of the sweep's log; a closed stdout (talus sweep | head) loses the log, not
    the sweep."""
    try:
        print(*args, flush=True)
    except (BrokenPipeError, OSError):
        pass


def fail(msg, code=2):
    print(f"error: sweep: {msg}", file=sys.stderr)
    sys.exit(code)


def write_atomic(path, text):
    """Writes text whole or not at all: a temporary file beside it, then a rename."""
    tmp = path.with_name(f".{path.name}.tmp{os.getpid()}")
    with open(tmp, "w") as f:
        f.write(text)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


# ------------------------------------------------------------------------------------------
# The design


def inverse_cdf(p, u):
    """The value of parameter p at probability u in (0, 1) of its (truncated) distribution."""
    if "values" in p:
        return p["values"][min(int(u * len(p["values"])), len(p["values"]) - 1)]
    kind = p["distribution"]
    lo, hi = p.get("range", (None, None))
    if kind == "uniform":
        return lo + (hi - lo) * u
    if kind == "triangular":
        c = (p["mode"] - lo) / (hi - lo)
        return lo + (hi - lo) * (math.sqrt(u * c) if u < c else 1.0 - math.sqrt((1 - u) * (1 - c)))
    if kind == "normal":
        d, f = NormalDist(p["mean"], p["sd"]), (lambda x: x)
    else:  # lognormal, by the mean and standard deviation of the value itself
        s2 = math.log(1.0 + (p["sd"] / p["mean"]) ** 2)
        d, f = NormalDist(math.log(p["mean"]) - s2 / 2, math.sqrt(s2)), math.exp
    if lo is not None:  # truncated to the range: u spread over the range's probabilities
        g = math.log if kind == "lognormal" else (lambda x: x)
        a = 0.0 if kind == "lognormal" and lo <= 0 else d.cdf(g(lo))
        u = a + (d.cdf(g(hi)) - a) * u
    return f(d.inv_cdf(min(max(u, 1e-12), 1 - 1e-12)))


def text(v):
    """A value as --set takes it: numbers to six significant digits, TOML text as given."""
    return f"{v:.6g}" if isinstance(v, float) else v


def design(plan):
    """The runs' parameter values (text), one dict per run, in run order."""
    params = plan["parameters"]
    if plan["design"] == "grid":
        axes = []
        for p in params:
            if "values" in p:
                axes.append(p["values"])
            else:
                lo, hi = p["range"]
                n = p["levels"]
                axes.append([text(lo + (hi - lo) * k / (n - 1)) for k in range(n)])
        return [dict(zip((p["key"] for p in params), combo)) for combo in product(*axes)]
    n = plan["runs"]
    rng = random.Random(plan["seed"])
    columns = []
    for p in params:
        strata = list(range(n))
        rng.shuffle(strata)
        columns.append([text(inverse_cdf(p, (s + rng.random()) / n)) for s in strata])
    return [{p["key"]: columns[j][i] for j, p in enumerate(params)} for i in range(n)]


# ------------------------------------------------------------------------------------------
# The runs


def summary(run):
    try:
        return json.loads((run / "summary.json").read_text())
    except (OSError, ValueError):
        return None


def status(run):
    s = summary(run)
    return s.get("status", "unknown") if s else ("absent" if not run.exists() else "unknown")


def die_with_parent():
    """A run started by the sweep gets SIGTERM (and checkpoints) if the sweep itself is killed."""
    try:
        import ctypes
        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG
    except OSError:
        pass


def child_environment():
    """This environment less what MPI set for this process (the mpi build's talus starts as a
    singleton): a run under a launcher (mpirun) must start its own job, not join this one."""
    keep = ("OMPI_ALLOW_RUN_AS_ROOT", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM")
    return {k: v for k, v in os.environ.items()
            if not k.startswith(("OMPI_", "PMIX_", "OPAL_", "PRTE_")) or k.startswith(keep)}


def wait_for_run_folder(run, seconds=120.0):
    """Waits while a run of an earlier, killed sweep still holds the folder (it is writing its
    checkpoint after the SIGTERM the sweep's death sent it): talus locks its marker while it runs."""
    marker = run / ".talus-run"
    if not marker.is_file():
        return
    end = time.time() + seconds
    with open(marker) as f:
        while True:
            try:
                fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
                fcntl.flock(f, fcntl.LOCK_UN)
                return
            except OSError:
                if time.time() > end:
                    fail(f"{run}: still in use by another run after {seconds:.0f} s")
                time.sleep(0.2)


class Runner:
    def __init__(self, args, plan, folder, names, values):
        self.a, self.plan, self.folder, self.names, self.values = args, plan, folder, names, values
        self.children = {}
        self.stopping = 0
        self.fresh = set()  # runs to start again (a restart that could not continue)
        (folder / "logs").mkdir(exist_ok=True)

    def command(self, i, fresh):
        run = self.folder / self.names[i]
        launcher = self.a.launcher.split() if self.a.launcher else []
        cmd = launcher + [self.a.talus, "run"]
        if not fresh:
            return cmd + ["--restart", str(run), "--threads", str(self.a.threads)]
        cmd += [self.plan["case"], "--out", str(run), "--threads", str(self.a.threads)]
        for o in self.plan["overrides"]:
            cmd += ["--set", o]
        for k, v in self.values[i].items():
            cmd += ["--set", f"{k}={v}"]
        if run.exists():
            cmd.append("--overwrite")  # the sweep's own run folder, left without a checkpoint
        return cmd

    def start(self, i):
        run = self.folder / self.names[i]
        wait_for_run_folder(run)
        checkpoints = run / "checkpoints"
        fresh = (i in self.fresh or status(run) in ("absent", "unknown") or
                 not (checkpoints.is_dir() and any(checkpoints.iterdir())))
        log = open(self.folder / "logs" / f"{self.names[i]}.log", "a")
        log.write(f"$ {' '.join(self.command(i, fresh))}\n")
        log.flush()
        child = subprocess.Popen(self.command(i, fresh), stdout=log, stderr=subprocess.STDOUT,
                                 preexec_fn=die_with_parent, env=child_environment())
        self.children[child.pid] = (child, i, fresh, log)

    def stop(self, sig, _frame):
        self.stopping = sig
        for child, *_ in self.children.values():
            child.send_signal(signal.SIGTERM)

    def run_all(self, todo):
        signal.signal(signal.SIGTERM, self.stop)
        signal.signal(signal.SIGINT, self.stop)
        queue = list(todo)
        while queue or self.children:
            while queue and len(self.children) < self.a.jobs and not self.stopping:
                i = queue.pop(0)
                self.start(i)
            if not self.children:
                break
            try:
                pid, wait_status = os.wait()
            except ChildProcessError:
                break
            if pid not in self.children:
                continue
            child, i, fresh, log = self.children.pop(pid)
            child.returncode = os.waitstatus_to_exitcode(wait_status)  # reaped here, not by Popen
            log.close()
            st = status(self.folder / self.names[i])
            say(f"{self.names[i]}: {st} ({child.returncode})")
            # A restart that could not continue (no usable checkpoint) starts the run again.
            if st not in ("completed", "failed") and not fresh and not self.stopping:
                self.fresh.add(i)
                queue.insert(0, i)
        if self.stopping:
            fail("interrupted: resume with the same command (done runs are kept)",
                 128 + self.stopping)


# ------------------------------------------------------------------------------------------
# Table, probability maps, scores


def lookup(results, path):
    v = results
    for part in path.split("."):
        if not isinstance(v, dict) or part not in v:
            return None
        v = v[part]
    return v if isinstance(v, (int, float)) and not isinstance(v, bool) else None


def read_raster(path):
    import rasterio
    with rasterio.open(path) as r:
        return r.read(1, masked=True), r.profile, r.transform


def observed_mask(path, shape, transform):
    """The cells whose centres lie in the observed outline's polygons (GeoJSON, map coordinates)."""
    from rasterio import features
    data = json.loads(Path(path).read_text())
    feats = data["features"] if data.get("type") == "FeatureCollection" else [data]
    geoms = [f.get("geometry", f) for f in feats]
    geoms = [g for g in geoms if g and g.get("type") in ("Polygon", "MultiPolygon")]
    if not geoms:
        fail(f"{path}: no polygon in the observed outline")
    return features.rasterize([(g, 1) for g in geoms], out_shape=shape, transform=transform,
                              fill=0, dtype="uint8").astype(bool)


def contingency(sim, obs, cell_area):
    tp, fp, fn = int((sim & obs).sum()), int((sim & ~obs).sum()), int((~sim & obs).sum())
    return dict(csi=tp / (tp + fp + fn) if tp + fp + fn else 0.0,
                hit_rate=tp / (tp + fn) if tp + fn else 0.0,
                false_area_m2=fp * cell_area, missed_area_m2=fn * cell_area)


def scores(run, plan, results, cache):
    """The run's scores against [observed]; cache holds the observed masks by grid."""
    o = plan.get("observed")
    if not o:
        return {}
    out = {}
    maps = run / "maps"
    if "impact_area" in o or "deposit_thickness" in o:
        import numpy as np
        h, profile, transform = read_raster(maps / "peak_thickness.tif")
        shape = h.shape
        cell_area = abs(transform.a * transform.e)
        if "impact_area" in o:
            key = ("impact", shape, tuple(transform))
            if key not in cache:
                cache[key] = observed_mask(o["impact_area"], shape, transform)
            obs = cache[key]
            sim = h.filled(0) > 0
            c = contingency(sim, obs, cell_area)
            out.update({"csi": c["csi"], "observed_area_reached": c["hit_rate"],
                        "area_reached_not_observed_m2": c["false_area_m2"],
                        "observed_area_missed_m2": c["missed_area_m2"]})
            cr = (results.get("maps") or {}).get("crown")
            if cr and obs.any():
                rows, cols = np.nonzero(obs)
                xs, ys = transform * (cols + 0.5, rows + 0.5)
                observed_length = float(np.max(np.hypot(xs - cr[0], ys - cr[1])))
                sim_length = lookup(results, "maps.runout_length_m")
                if sim_length is not None:
                    out["runout_difference_m"] = sim_length - observed_length
        if "deposit_thickness" in o:
            d, _, _ = read_raster(maps / "deposit_thickness.tif")
            od, _, otr = read_raster(o["deposit_thickness"])
            if od.shape != shape or tuple(otr) != tuple(transform):
                fail(f"{o['deposit_thickness']}: the observed deposit is not on the maps' grid "
                     f"({od.shape[1]} x {od.shape[0]} cells against {shape[1]} x {shape[0]})")
            t = o["deposit_threshold"]
            sim, obs = d.filled(0) > t, od.filled(0) > t
            c = contingency(sim, obs, cell_area)
            both = sim | obs
            rmse = float(np.sqrt(np.mean((d.filled(0) - od.filled(0))[both] ** 2))) \
                if both.any() else 0.0
            out.update({"deposit_csi": c["csi"], "deposit_thickness_rmse_m": rmse})
    misses = []
    for key, (lo, hi) in o.get("figures", {}).items():
        v = lookup(results, key)
        if v is None:
            out[f"miss:{key}"] = None
            continue
        miss = 0.0 if lo <= v <= hi else (v - hi) / abs(hi) if v > hi else (v - lo) / abs(lo)
        out[f"miss:{key}"] = miss
        misses.append(miss)
    if o.get("figures"):
        out["figures_rms_miss"] = math.sqrt(sum(m * m for m in misses) / len(misses)) \
            if len(misses) == len(o["figures"]) else None
    return out


def fmt(v):
    if v is None:
        return ""
    if isinstance(v, float):
        return f"{v:.6g}"
    return str(v)


def probability_maps(folder, names, completed, plan):
    """The share of completed runs exceeding each threshold, per cell (3D) or along x (2D)."""
    import numpy as np
    maps = folder / "maps"
    maps.mkdir(exist_ok=True)
    runs = [folder / names[i] for i in completed]
    if not runs:
        return []
    exceed = [("peak_thickness", 0.0)] + [(f, t) for f, ts in plan["exceed"].items() for t in ts]
    if plan["dimension"] == 2:
        counts, x = {}, None
        for run in runs:
            rows = np.genfromtxt(run / "maps" / "profile.csv", delimiter=",", names=True,
                                 skip_header=1)
            if x is None:
                x = rows["x"]
            elif len(rows["x"]) != len(x) or not np.array_equal(rows["x"], x):
                fail(f"{run}: its profile's cells differ from the first run's")
            for f, t in exceed:
                counts[(f, t)] = counts.get((f, t), 0) + (np.nan_to_num(rows[f]) > t)
        header = ["x"] + [("reached" if t == 0 else f"{f}_above_{t:g}") for f, t in exceed]
        lines = [f"# share of {len(runs)} completed runs", ",".join(header)]
        for k in range(len(x)):
            lines.append(",".join([f"{x[k]:.6g}"] + [f"{counts[e][k] / len(runs):.6g}"
                                                     for e in exceed]))
        target = maps / "probability_profile.csv"
        write_atomic(target, "\n".join(lines) + "\n")
        return [target]
    import rasterio
    first = None
    counts = {}
    for run in runs:
        for f in sorted({f for f, _ in exceed}):
            data, profile, transform = read_raster(run / "maps" / f"{f}.tif")
            if first is None:
                first = (profile, transform, data.mask.copy())
            elif data.shape != first[2].shape or tuple(transform) != tuple(first[1]):
                fail(f"{run}: its maps' grid differs from the first run's (a swept key changes "
                     "the map grid: sweep it in separate sweeps)")
            for ff, t in exceed:
                if ff == f:
                    counts[(f, t)] = counts.get((f, t), 0) + (data.filled(0) > t)
    profile, transform, mask = first
    profile.update(dtype="float32", nodata=-9999.0, compress="deflate", count=1)
    written = []
    for f, t in exceed:
        stem = "probability_reached" if t == 0 else f"probability_{f}_above_{t:g}"
        share = np.where(mask, -9999.0, counts[(f, t)] / len(runs)).astype("float32")
        what = ("reached by moving material" if t == 0 else
                f"{f.replace('_', ' ')} above {t:g} {MAP_FIELDS[f]}")
        tmp = maps / f".{stem}.tif.tmp{os.getpid()}"
        with rasterio.open(tmp, "w", driver="GTiff", **{k: v for k, v in profile.items()
                                                      if k != "driver"}) as w:
            w.write(share, 1)
            w.set_band_description(1, stem)
            w.update_tags(1, DESCRIPTION=f"share of {len(runs)} runs {what}")
            w.units = ("share of runs",)
            w.update_tags(TALUS_RUNS=str(len(runs)), TALUS_CASE=plan["case"])
        os.replace(tmp, maps / f"{stem}.tif")
        written.append(maps / f"{stem}.tif")
    # The ground and the release area under the pictures: the first run's (every run has the
    # same ground; the release may differ if a swept key moves it).
    for stem in ("elevation", "release_thickness"):
        src = runs[0] / "maps" / f"{stem}.tif"
        if src.exists():
            tmp = maps / f".{stem}.tif.tmp{os.getpid()}"
            tmp.write_bytes(src.read_bytes())
            os.replace(tmp, maps / f"{stem}.tif")
    return written


# ------------------------------------------------------------------------------------------


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--talus", required=True)
    ap.add_argument("--plan", required=True, help="the validated [sweep] and [observed] (JSON)")
    ap.add_argument("--out", required=True)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=0)
    ap.add_argument("--launcher", default="")
    a = ap.parse_args()
    plan = json.loads(a.plan)
    a.jobs = a.jobs or max(1, (os.cpu_count() or 1) // a.threads)
    values = design(plan)
    width = max(3, len(str(len(values) - 1)))
    names = [f"run_{i:0{width}d}" for i in range(len(values))]

    # The sweep folder: new, or this sweep's own (same plan and design), locked while in use.
    folder = Path(a.out)
    # The case file's bytes are part of the record: a case edited since the sweep began would mix
    # two cases in one table.
    case_hash = hashlib.sha256(Path(plan["case"]).read_bytes()).hexdigest()
    record = {"plan": plan, "case_sha256": case_hash,
              "runs": [{"run": n, "set": v} for n, v in zip(names, values)]}
    if folder.exists() and not folder.is_dir():
        fail(f"{folder}: not a folder")
    folder.mkdir(parents=True, exist_ok=True)
    lock = open(folder / ".talus_sweep.lock", "a")
    try:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        fail(f"{folder}: another sweep is running in this folder")
    existing = folder / PLAN_FILE
    if existing.exists():
        try:
            before = json.loads(existing.read_text())
        except ValueError:
            fail(f"{existing}: unreadable; give another --out")
        if before != record:
            what = ("the case file changed since it began" if before.get("plan") == plan
                    else "its case, overrides or design differ")
            fail(f"{folder}: holds another sweep ({what}): give another --out")
    else:
        foreign = [p.name for p in folder.iterdir() if p.name != ".talus_sweep.lock"]
        if foreign:
            fail(f"{folder}: holds files talus sweep did not write ({', '.join(sorted(foreign)[:5])}"
                 "): give another --out")
        write_atomic(existing, json.dumps(record, indent=1) + "\n")

    done = [i for i, n in enumerate(names) if status(folder / n) in ("completed", "failed")]
    todo = [i for i in range(len(names)) if i not in done]
    say(f"sweep: {len(names)} runs ({len(done)} done), {a.jobs} at a time, {a.threads} "
          f"thread{'s' if a.threads > 1 else ''} each, in {folder}")
    t0 = time.time()
    Runner(a, plan, folder, names, values).run_all(todo)
    say(f"sweep: runs done in {time.time() - t0:.0f} s")

    # The table (and the ranking), from every run's summary.json.
    summaries = [summary(folder / n) or {} for n in names]
    results = [s.get("results", {}) for s in summaries]
    figures = [f for f in FIGURES if any(lookup(r, f) is not None for r in results)]
    figures += [k for k in plan.get("observed", {}).get("figures", {}) if k not in figures]
    cache, rows = {}, []
    completed = [i for i, s in enumerate(summaries) if s.get("status") == "completed"]
    for i, n in enumerate(names):
        row = {"run": n, **values[i], "status": summaries[i].get("status", "absent")}
        row.update({f: lookup(results[i], f) for f in figures})
        if i in completed:
            row.update(scores(folder / n, plan, results[i], cache))
        rows.append(row)
    columns = list(dict.fromkeys(k for r in rows for k in r))

    def table(rs, extra=()):
        lines = [",".join(list(extra) + columns)]
        for r in rs:
            lines.append(",".join([fmt(x) for x in r.get("_extra", [])] +
                                  [fmt(r.get(c)) for c in columns]))
        return "\n".join(lines) + "\n"

    write_atomic(folder / "table.csv", table(rows))
    say(f"wrote {folder / 'table.csv'}")
    written = probability_maps(folder, names, completed, plan) if plan["maps"] else []
    for w in written:
        say(f"wrote {w}")
    if "observed" in plan:
        o = plan["observed"]
        by = ("csi" if "impact_area" in o else "deposit_csi" if "deposit_thickness" in o
              else "figures_rms_miss")
        better = -1 if by != "figures_rms_miss" else 1
        ranked = sorted((r for r in rows if r.get(by) is not None),
                        key=lambda r: (better * r[by], r["run"]))
        for k, r in enumerate(ranked):
            r["_extra"] = [k + 1]
        write_atomic(folder / "ranking.csv", table(ranked, extra=["rank"]))
        say(f"wrote {folder / 'ranking.csv'} (by {by})")
        keys = [p["key"] for p in plan["parameters"]]
        for r in ranked[:5]:
            say(f"  {r['_extra'][0]:>3}  {r['run']}  {by} {fmt(r[by])}  " +
                  "  ".join(f"{k}={r[k]}" for k in keys))
    failed = [n for n, s in zip(names, summaries) if s.get("status") != "completed"]
    if failed:
        say(f"sweep: {len(failed)} run(s) not completed: {', '.join(failed[:10])} (their logs: "
              f"{folder / 'logs'})")
    if written and plan["dimension"] == 3:
        subprocess.run([sys.executable, str(Path(__file__).with_name("plot_maps.py")),
                        str(folder)], check=False)


if __name__ == "__main__":
    main()
