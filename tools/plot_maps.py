#!/usr/bin/env python3
"""Map pictures of a run's hazard maps (RUN_DIR/maps/*.tif, written by a case's [maps]): each
field drawn over the ground's hillshade with its contours, the release area's outline (where the
release thickness is above zero), a labelled colour bar, a scale bar and a north arrow, in map
coordinates (the rasters' own, the [terrain] origin added back), framed on the area the bodies
reached with a margin of half its size (--whole: the whole raster). Cells the field never
reached are left clear; the intensity classes are drawn in the colours of Swiss hazard maps
(low yellow, medium blue, high red) with their thresholds. Written to RUN_DIR/plots/map_FIELD.png (or --out DIR).
A sweep's folder (talus sweep) is drawn the same way: its probability maps
(maps/probability_*.tif, the share of the runs), over the first run's ground.

A 2D run's maps (maps/profile.csv) are drawn as its profile along the section: thickness
(peak, deposit, release), peak speed (shaded by intensity class: blue medium, red high) and
arrival time against x, in RUN_DIR/plots/profile.png.

Usage: plot_maps.py RUN_DIR [--out DIR] [--contour M] [--whole]
"""
import argparse
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402
import numpy as np  # noqa: E402
import rasterio  # noqa: E402

# The fields drawn: file stem -> (title, colour map).
FIELDS = {
    "peak_thickness": ("Peak flow thickness", "viridis"),
    "peak_speed": ("Peak depth-averaged speed", "plasma"),
    "peak_kinetic_energy": ("Peak kinetic energy per unit area", "magma"),
    "peak_pressure": ("Peak dynamic pressure", "inferno"),
    "arrival_time": ("Arrival time after release", "cividis_r"),
    "deposit_thickness": ("Deposit thickness", "viridis"),
    "thickness_change": ("Change of the ground surface", "RdBu_r"),
    # The classes in the colours of Swiss hazard maps: low yellow, medium blue, high red.
    "intensity": ("Intensity class", ListedColormap(["#f2d40f", "#2f6fd6", "#d7191c"])),
}

ap = argparse.ArgumentParser()
ap.add_argument("run")
ap.add_argument("--out")
ap.add_argument("--contour", type=float, help="contour interval of the ground (m; default: "
                "about ten contours over its range)")
ap.add_argument("--whole", action="store_true", help="draw the whole raster, not the area reached")
a = ap.parse_args()
run = Path(a.run)
maps = run / "maps"
if not maps.is_dir():
    raise SystemExit(f"{maps}: no maps (the case has no [maps] table)")
out = Path(a.out) if a.out else run / "plots"
out.mkdir(parents=True, exist_ok=True)


def plot_profile(path):
    """A 2D run's maps: the profile along the section (maps/profile.csv) as three panels."""
    rows = np.genfromtxt(path, delimiter=",", names=True, skip_header=1)
    x = rows["x"]
    fig, axes = plt.subplots(3, 1, figsize=(8.0, 7.5), sharex=True)
    axes[0].fill_between(x, rows["release_thickness"], step="mid", color="0.8",
                         label="release")
    axes[0].step(x, rows["peak_thickness"], where="mid", color="C0", label="peak (moving)")
    axes[0].step(x, rows["deposit_thickness"], where="mid", color="C3", label="deposit")
    axes[0].set_ylabel("thickness (m)")
    axes[0].legend(fontsize=8)
    axes[1].step(x, rows["peak_speed"], where="mid", color="C1")
    axes[1].set_ylabel("peak speed (m/s)")
    for level, colour in ((2, "#2f6fd6"), (3, "#d7191c")):
        band = rows["intensity"] == level
        axes[1].fill_between(x, 0, rows["peak_speed"], where=band, step="mid", color=colour,
                             alpha=0.25)
    axes[2].step(x, rows["arrival_time"], where="mid", color="C2")
    axes[2].set_ylabel("arrival time (s)")
    axes[2].set_xlabel("x (m)")
    with open(path) as f:
        axes[0].set_title("Profile along the section: " + f.readline().lstrip("# ").split(";")[0],
                          fontsize=9)
    fig.tight_layout()
    target = out / "profile.png"
    fig.savefig(target, dpi=130)
    plt.close(fig)
    print(f"wrote {target}")


if (maps / "profile.csv").exists():
    plot_profile(maps / "profile.csv")
    raise SystemExit(0)


def read(stem):
    path = maps / f"{stem}.tif"
    if not path.exists():
        return None, None, None
    with rasterio.open(path) as r:
        data = r.read(1, masked=True).astype(float).filled(np.nan)
        b = r.bounds
        unit = (r.units or ("",))[0]
        tags = r.tags()
    return data, (b.left, b.right, b.bottom, b.top), (unit, tags)


def band_description(stem):
    """The thresholds a class raster was made with, as its band's description states them."""
    with rasterio.open(maps / f"{stem}.tif") as r:
        text = r.tags(1).get("DESCRIPTION", "")
    return text.split(": ", 1)[-1].split("; no data")[0].replace("), ", "),\n")


def hillshade(z, dx, dy, azimuth=315.0, altitude=45.0):
    """Lambert shading of the ground lit from the north-west (rows run north to south)."""
    gy, gx = np.gradient(z, dy, dx)
    slope = np.arctan(np.hypot(gx, gy))
    aspect = np.arctan2(-gx, gy)
    az, alt = math.radians(azimuth), math.radians(altitude)
    shade = np.sin(alt) * np.cos(slope) + np.cos(alt) * np.sin(slope) * np.cos(az - aspect)
    return np.clip(shade, 0.0, 1.0)


def nice_length(span):
    """A round scale-bar length near a fifth of the map's width."""
    target = span / 5.0
    p = 10 ** math.floor(math.log10(target))
    return max(m * p for m in (1, 2, 5) if m * p <= target)


ground, extent, _ = read("elevation")
release, _, _ = read("release_thickness")
reached, full, _ = read("peak_thickness")
if reached is None:  # a sweep's folder: frame on the cells any run reached
    reached, full, _ = read("probability_reached")
if full is None:
    raise SystemExit(f"{maps}: no map to draw")
# A sweep's probability maps: the share of its runs above each threshold (tools/sweep.py).
PROBABILITY = {p.stem: (None, "YlOrRd") for p in sorted(maps.glob("probability_*.tif"))}


def frame():
    """The view: the cells reached (or released) and half their size around them."""
    left, right, bottom, top = full
    if a.whole or reached is None:
        return full
    mask = np.nan_to_num(reached) > 0
    if release is not None:
        mask |= np.nan_to_num(release) > 0
    if not mask.any():
        return full
    ny, nx = mask.shape
    dx, dy = (right - left) / nx, (top - bottom) / ny
    rows, cols = np.nonzero(mask)
    x0, x1 = left + cols.min() * dx, left + (cols.max() + 1) * dx
    y0, y1 = top - (rows.max() + 1) * dy, top - rows.min() * dy
    pad = 0.5 * max(x1 - x0, y1 - y0)
    return (max(left, x0 - pad), min(right, x1 + pad), max(bottom, y0 - pad), min(top, y1 + pad))


view = frame()
written = []
for stem, (title, cmap) in {**FIELDS, **PROBABILITY}.items():
    data, ext, meta = read(stem)
    if data is None:
        continue
    unit, tags = meta
    share = stem in PROBABILITY
    if share:
        title = band_description(stem).replace("share of", "Share of", 1)
    signed = stem == "thickness_change"  # erosion (negative) and deposition (positive)
    if signed:
        shown = np.where(np.isnan(data) | (data == 0.0), np.nan, data)
    else:
        shown = np.where(np.isnan(data) | (data <= 0.0) & (stem != "arrival_time"), np.nan, data)
    fig, ax = plt.subplots(figsize=(7.5, 7.0))
    left, right, bottom, top = ext
    ny, nx = data.shape
    dx, dy = (right - left) / nx, (top - bottom) / ny
    if ground is not None:
        z = np.where(np.isnan(ground), np.nanmean(ground), ground)
        ax.imshow(hillshade(z, dx, dy), extent=ext, cmap="gray", vmin=0.0, vmax=1.0)
        xs = left + (np.arange(nx) + 0.5) * dx
        ys = top - (np.arange(ny) + 0.5) * dy
        step = a.contour or nice_length((np.nanmax(ground) - np.nanmin(ground)) * 5.0 / 20.0)
        levels = np.arange(math.floor(np.nanmin(ground) / step) * step, np.nanmax(ground) + step,
                           step)
        cs = ax.contour(xs, ys, ground, levels=levels, colors="k", linewidths=0.4, alpha=0.5)
        ax.clabel(cs, fontsize=6, fmt="%.0f")
    classes = stem == "intensity"
    im = ax.imshow(shown, extent=ext, cmap=cmap, alpha=0.85, interpolation="nearest",
                   **(dict(vmin=0.5, vmax=3.5) if classes else {}),
                   **(dict(vmin=0.0, vmax=1.0) if share else {}),
                   **(dict(vmin=-np.nanmax(np.abs(shown)), vmax=np.nanmax(np.abs(shown)))
                      if signed and np.isfinite(shown).any() else {}))
    if release is not None and np.nanmax(release) > 0.0:
        xs = left + (np.arange(nx) + 0.5) * dx
        ys = top - (np.arange(ny) + 0.5) * dy
        ax.contour(xs, ys, np.nan_to_num(release), levels=[1e-6], colors="w", linewidths=1.6)
        ax.plot([], [], color="w", lw=1.6, label="release area")
        ax.legend(loc="lower left", fontsize=8, facecolor="0.3", labelcolor="w", framealpha=0.8)
    bar = fig.colorbar(im, ax=ax, shrink=0.8, **(dict(ticks=[1, 2, 3]) if classes else {}))
    if classes:
        bar.ax.set_yticklabels(["low", "medium", "high"])
        bar.set_label(f"{title.lower()}: {band_description(stem)}", fontsize=7)
    elif share:
        bar.set_label("share of the runs")
    else:
        bar.set_label(f"{title.lower()} ({unit})")
    # Framed on the view; scale bar (bottom right) and north arrow (top right) in its metres.
    vl, vr, vb, vt = view
    ax.set_xlim(vl, vr)
    ax.set_ylim(vb, vt)
    length = nice_length(vr - vl)
    x0, y0 = vr - (vr - vl) * 0.05 - length, vb + (vt - vb) * 0.05
    ax.plot([x0, x0 + length], [y0, y0], color="k", lw=4, solid_capstyle="butt")
    ax.plot([x0, x0 + length], [y0, y0], color="w", lw=2, solid_capstyle="butt")
    ax.text(x0 + length / 2, y0 + (vt - vb) * 0.015, f"{length:g} m", ha="center",
            va="bottom", fontsize=8, bbox=dict(fc="w", ec="none", alpha=0.7, pad=1))
    ax.annotate("N", xy=(0.94, 0.95), xytext=(0.94, 0.83), xycoords="axes fraction",
                ha="center", va="center", fontsize=11, fontweight="bold",
                arrowprops=dict(facecolor="k", width=3, headwidth=10))
    ax.set_xlabel("easting (m)")
    ax.set_ylabel("northing (m)")
    ax.set_aspect("equal")
    bodies = tags.get("TALUS_BODIES", "")
    if share:
        ax.set_title(title, fontsize=10)
    else:
        ax.set_title(f"{title}: {bodies}\nmoving above {tags.get('TALUS_MOVING_SPEED_M_S', '?')} m/s, "
                     f"at t = {float(tags.get('TALUS_TIME_S', 'nan')):.3g} s",
                     fontsize=10)
    ax.ticklabel_format(useOffset=False, style="plain")
    fig.tight_layout()
    path = out / f"map_{stem}.png"
    fig.savefig(path, dpi=130)
    plt.close(fig)
    written.append(path)
for p in written:
    print(f"wrote {p}")
if not written:
    raise SystemExit(f"{maps}: no map to draw")
