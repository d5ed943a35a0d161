#!/usr/bin/env python3
"""The Vaiont figures of a run folder (docs/vaiont.md, issue #6):
  frames.png            bodies and equivalent plastic strain at 10, 17.5, 22.5, 33.5 s (Figure 13)
  probe_speed.png       the probes' speed against time (Figure 15)
  speed_displacement.png the slide's mass-averaged speed against its centroid's displacement
                        (Figure 16)
  profile.png           the final ground surface against the pre-slide ground line
  release_stress.png    vertical stress down a vertical line through the slide at release,
                        against the weight of the particles above
  vaiont.json           the deposit's figures of the last frame: the front's run-up height on the
                        north slope, how far north the slide reached, and the final ground
                        surface against the pre-slide line (printed too); with the reservoir as a
                        body (--lake), the wave's figures too (below)
  lake.png              with the reservoir as a body: the valley at six times, the water apart

Usage: plot_vaiont.py RUN_DIR [--section cases/vaiont/section.csv] [--out DIR]
"""
import argparse
import csv
import json
import tomllib
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import talus_frames  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("run")
ap.add_argument("--section", default=str(Path(__file__).parent.parent / "cases/vaiont/section.csv"))
ap.add_argument("--out")
ap.add_argument("--times", type=float, nargs="+", default=[10.0, 17.5, 22.5, 33.5])
ap.add_argument("--body", help="the body of the speed and stress plots (default: the case's "
                "[results] body, else slide)")
ap.add_argument("--slide", default="slide,upper,middle,toe",
                help="the bodies that make up the slide (those present are used)")
ap.add_argument("--lake", default="lake", help="the reservoir's body, if the run has it")
ap.add_argument("--spacing", type=float, default=4.0,
                help="particle spacing (m) if the frames carry no volume field")
a = ap.parse_args()
run = Path(a.run)
case = tomllib.loads((run / "case_as_run.toml").read_text())
a.body = a.body or case.get("results", {}).get("body", "slide")
out = Path(a.out) if a.out else run / "plots"
out.mkdir(parents=True, exist_ok=True)
frames = talus_frames.times(run)
section = {}
with open(a.section) as f:
    for r in csv.DictReader(f):
        section.setdefault(r["line"], []).append((float(r["x"]), float(r["z"])))
ground = np.array(section["ground_before"])
colours = np.array(["#8c564b", "#9e9e9e", "#2ca02c", "#1f77b4", "#ff7f0e", "#9467bd"])


def frame(t):
    return talus_frames.nearest(run, t, frames)


# Bodies and plastic strain at the paper's times.
fig, axes = plt.subplots(2, len(a.times), figsize=(4.6 * len(a.times), 6.4), squeeze=False)
for j, t in enumerate(a.times):
    tf, m = frame(t)
    x = m.points[:, :2]
    body = m.point_data["body"].ravel().astype(int)
    ax = axes[0][j]
    ax.scatter(x[:, 0], x[:, 1], s=0.3, c=colours[body % len(colours)], linewidths=0)
    ax.set_title(f"t = {tf:.1f} s: bodies")
    ax = axes[1][j]
    eps = m.point_data.get("plastic_strain", np.zeros(len(x))).ravel()
    sc = ax.scatter(x[:, 0], x[:, 1], s=0.3, c=np.clip(eps, 0, 1), cmap="inferno_r", vmin=0,
                    vmax=1, linewidths=0)
    ax.set_title(f"t = {tf:.1f} s: plastic strain")
    for ax in axes[:, j]:
        ax.plot(ground[:, 0], ground[:, 1], "k--", lw=0.6)
        ax.set_aspect("equal")
fig.colorbar(sc, ax=axes[1].tolist(), shrink=0.8, label="equivalent plastic strain (clipped at 1)")
fig.savefig(out / "frames.png", dpi=100)
plt.close(fig)

# Probe speeds.
rows = list(csv.DictReader(open(run / "probes.csv")))
fig, ax = plt.subplots(figsize=(6, 3.8))
for name in dict.fromkeys(r["probe"] for r in rows):
    sel = [r for r in rows if r["probe"] == name]
    ax.plot([float(r["time"]) for r in sel], [float(r["speed"]) for r in sel], label=name)
ax.set_xlabel("time after release (s)")
ax.set_ylabel("speed (m/s)")
ax.legend()
ax.grid(alpha=0.3)
fig.tight_layout()
fig.savefig(out / "probe_speed.png", dpi=100)
plt.close(fig)

# Speed against displacement.
rows = [r for r in csv.DictReader(open(run / "bodies.csv")) if r["body"] == a.body]
cx = np.array([float(r["centroid_x"]) for r in rows])
cy = np.array([float(r["centroid_y"]) for r in rows])
d = np.hypot(cx - cx[0], cy - cy[0])
fig, ax = plt.subplots(figsize=(6, 3.8))
ax.plot(d, [float(r["mean_speed"]) for r in rows])
ax.set_xlabel(f"{a.body} centroid displacement (m)")
ax.set_ylabel(f"{a.body} mass-averaged speed (m/s)")
ax.grid(alpha=0.3)
fig.tight_layout()
fig.savefig(out / "speed_displacement.png", dpi=100)
plt.close(fig)


def surface(m, width):
    """The top of the ground (every body but the lake's water) in bins of `width` along x."""
    x = m.points[:, :2]
    if a.lake in body_names:
        x = x[m.point_data["body"].ravel().astype(int) != body_names.index(a.lake)]
    bins = np.floor(x[:, 0] / width).astype(int)
    top = {}
    for b, y in zip(bins, x[:, 1]):
        top[b] = max(top.get(b, -np.inf), y)
    k = np.array(sorted(top))
    return (k + 0.5) * width, np.array([top[i] for i in k])


# Final ground surface.
t0, m0 = frame(0.0)
tf, mf = frame(frames[-1][0])
spacing = np.sqrt(np.median(m0.point_data["volume"])) if "volume" in m0.point_data else a.spacing
body_names = list(dict.fromkeys(r["body"] for r in csv.DictReader(open(run / "bodies.csv"))))
slide_ids = [i for i, n in enumerate(body_names) if n in a.slide.split(",")]
if not slide_ids:
    raise SystemExit(f"plot_vaiont.py: none of the bodies {a.slide} is in {run / 'bodies.csv'}")
slide_final = np.isin(mf.point_data["body"].ravel().astype(int), slide_ids)
xf = mf.points[slide_final, :2]
# The north slope starts where the pre-slide ground leaves the valley floor (its lowest level)
# for the last time. The run-up is the highest point of that slope the slide's material reached:
# its highest particle north of the foot lying on the slope (within two spacings of the pre-slide
# ground line), as a height above the floor.
floor = ground[:, 1].min()
foot = ground[ground[:, 1] == floor, 0].max()
on_slope = (xf[:, 0] > foot) & (xf[:, 1] - np.interp(xf[:, 0], ground[:, 0], ground[:, 1]) <
                                2 * spacing)
top = int(np.argmax(np.where(on_slope, xf[:, 1], -np.inf))) if on_slope.any() else None
xs, ys = surface(mf, 2 * spacing)
before = np.interp(xs, ground[:, 0], ground[:, 1])
change = ys - before
figures = {
    "time_s": tf,
    "slide_bodies": [body_names[i] for i in slide_ids],
    "north_slope_foot_x_m": foot,
    "run_up_height_m": float(xf[top, 1] - floor) if top is not None else 0.0,
    "run_up_x_m": float(xf[top, 0]) if top is not None else None,
    "front_x_m": float(xf[:, 0].max()),
    "surface_bin_m": 2 * spacing,
    "largest_rise_m": float(change.max()), "largest_rise_x_m": float(xs[change.argmax()]),
    "largest_drop_m": float(change.min()), "largest_drop_x_m": float(xs[change.argmin()]),
    "valley_floor_fill_m": float(ys[(xs >= ground[ground[:, 1] == floor, 0].min()) &
                                    (xs <= foot)].max() - floor),
}
# The reservoir as a body: the wave's figures over every frame. The water's run-up is the highest
# point of the north slope (north of its foot) that the lake's water reached, above the lake's
# level (the case's [[run_up]] probe on the lake when it has one); the water that left the section is the lake's lost mass over its density (outflow face);
# the wave over the valley's middle is the highest reading of the gauge there above the level;
# the share of the slide's energy is the lake's peak kinetic energy over the slide's.
if a.lake in body_names:
    level = case.get("water", {}).get("level", 0.0)
    lake = body_names.index(a.lake)
    # The run's own run-up probe on the lake (summary.json, checked every step) if it has one;
    # else the highest water particle north of the slope's foot in the frames.
    probes = json.loads((run / "summary.json").read_text())["results"].get("run_up", {})
    probe = next((p for p in probes.values() if p["body"] == a.lake and p["elevation_m"]), None)
    best = (-np.inf, None)
    if probe:
        best = (probe["elevation_m"], probe["time_s"])
    else:
        for t, f in frames:
            m = talus_frames.read(run, f)
            w = m.points[m.point_data["body"].ravel().astype(int) == lake, :2]
            north = w[w[:, 0] > foot]
            if len(north) and north[:, 1].max() > best[0]:
                best = (float(north[:, 1].max()), t)
    w0 = m0.point_data["body"].ravel().astype(int) == lake
    rho_w = float(m0.point_data["mass"].ravel()[w0].sum() / m0.point_data["volume"].ravel()[w0].sum())
    rows = list(csv.DictReader(open(run / "bodies.csv")))
    lake_mass = [float(r["mass"]) for r in rows if r["body"] == a.lake]
    # The slide's kinetic energy: all its bodies' at each row's time (five bodies: three parts).
    slide_names = [body_names[i] for i in slide_ids]
    lake_ke = max(float(r["kinetic_energy"]) for r in rows if r["body"] == a.lake)
    slide_ke = {}
    for r in rows:
        if r["body"] in slide_names:
            slide_ke[r["time"]] = slide_ke.get(r["time"], 0.0) + float(r["kinetic_energy"])
    gauge = [(float(r["elevation"]), float(r["time"]))
             for r in csv.DictReader(open(run / "waves.csv"))
             if r["gauge"] == "valley_middle" and r["elevation"]] if (run / "waves.csv").exists() \
        else []
    figures.update({
        "lake_level_m": level,
        "lake_run_up_m": best[0] - level, "lake_run_up_time_s": best[1],
        "lake_left_section_m2": (lake_mass[0] - lake_mass[-1]) / rho_w,
        "lake_area_m2": lake_mass[0] / rho_w,
        # The water's surface over the valley's middle, the slide under it or not.
        "wave_over_valley_middle_m": (max(gauge)[0] - level) if gauge else None,
        "wave_over_valley_middle_time_s": max(gauge)[1] if gauge else None,
        "lake_share_of_slide_kinetic_energy": lake_ke / max(slide_ke.values()),
    })
    times = [6.0, 10.0, 14.0, 18.0, 26.0, frames[-1][0]]
    fig, axes = plt.subplots(2, 3, figsize=(14, 6.4))
    for ax, t in zip(axes.ravel(), times):
        tf, m = frame(t)
        x = m.points[:, :2]
        body = m.point_data["body"].ravel().astype(int)
        # The water blue, the slide grey, the bedrock tan, the old deposit brown.
        shade = {a.lake: "#1f77b4", "bedrock": "#d9c9a3", "deposit": "#8c564b"}
        palette = np.array([shade.get(n, "#9e9e9e") for n in body_names])
        ax.scatter(x[:, 0], x[:, 1], s=0.4, linewidths=0, c=palette[body])
        ax.plot(ground[:, 0], ground[:, 1], "k--", lw=0.6)
        ax.axhline(level, color="#1f77b4", lw=0.5, ls=":")
        ax.set_xlim(800, ground[:, 0].max() + 40)
        ax.set_ylim(-60, 420)
        ax.set_aspect("equal")
        ax.set_title(f"t = {tf:.1f} s", fontsize=9)
    fig.suptitle(f"The reservoir as a body (blue): water run-up {figures['lake_run_up_m']:.0f} m "
                 f"above the lake, {figures['lake_left_section_m2']:.0f} m^2 over the section's "
                 "end", fontsize=10)
    fig.tight_layout()
    fig.savefig(out / "lake.png", dpi=110)
    plt.close(fig)
(out / "vaiont.json").write_text(__import__("json").dumps(figures, indent=2) + "\n")
print("vaiont.json:", figures)
fig, ax = plt.subplots(figsize=(9, 4))
ax.plot(ground[:, 0], ground[:, 1], "k--", label="ground before the slide (section.csv)")
xs0, ys0 = surface(m0, 2 * spacing)
ax.plot(xs0, ys0, color="#1f77b4", lw=0.8, label="surface at release")
ax.plot(xs, ys, color="#d62728", label=f"surface at t = {tf:.1f} s")
if top is not None:
    ax.plot(*xf[top], "kv", ms=5, label=f"run-up {figures['run_up_height_m']:.0f} m above the floor")
ax.set_xlabel("x (m)")
ax.set_ylabel("elevation (m)")
ax.set_aspect("equal")
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(out / "profile.png", dpi=100)
plt.close(fig)

# Vertical stress at release down a vertical line through the slide's centroid (if the frames
# carry the stress).
written = ["frames.png", "probe_speed.png", "speed_displacement.png", "profile.png", "vaiont.json"]
if a.lake in body_names:
    written.append("lake.png")
if "stress" in m0.point_data:
    x = m0.points[:, :2]
    body = m0.point_data["body"].ravel().astype(int)
    slide = body == list(dict.fromkeys(r["body"] for r in csv.DictReader(open(run / "bodies.csv")))).index(a.body)
    xc = x[slide, 0][np.argmin(np.abs(x[slide, 0] - x[slide, 0].mean()))]  # a particle column
    col = np.abs(x[:, 0] - xc) < 0.5 * spacing
    order = np.argsort(-x[col, 1])
    y = x[col, 1][order]
    syy = m0.point_data["stress"][col, 1][order]
    mass = m0.point_data["mass"].ravel()[col][order] if "mass" in m0.point_data else None
    fig, ax = plt.subplots(figsize=(5, 5))
    for b in np.unique(body[col]):
        sel = body[col][order] == b
        ax.plot(-syy[sel] / 1e6, y[sel], ".", ms=3, color=colours[b % len(colours)])
    if mass is not None:
        width = spacing  # one column of particles, one spacing wide
        overburden = np.cumsum(mass) * 9.81 / width - 0.5 * mass * 9.81 / width
        ax.plot(overburden / 1e6, y, "k-", lw=1, label="weight of the particles above")
        ax.legend(fontsize=8)
    ax.set_xlabel("-sigma_yy (MPa)")
    ax.set_ylabel("elevation (m)")
    ax.set_title(f"at release, x = {xc:.0f} m")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "release_stress.png", dpi=100)
    plt.close(fig)
    written.append("release_stress.png")
print("wrote", ", ".join(str(out / n) for n in written))
