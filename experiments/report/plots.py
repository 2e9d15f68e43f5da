"""The report's plots (matplotlib, Agg): error against time and samples, the
crop's error against time, and efficiency at the final snapshot.

One colour per configuration across every plot and the image grid; unbiased
configurations are drawn solid, biased or consistent ones dashed. Each curve
is the median over repeats; the shaded band is the min-max over repeats.
"""
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from runlog import band  # noqa: E402

plt.rcParams.update({"font.size": 9, "axes.titlesize": 10, "legend.fontsize": 8, "svg.fonttype": "none"})

# (log column, x key, axis label, panel title)
PANELS = {
    "rmse_vs_time": ("rmse", "time_s", "time (s)", "RMSE vs time"),
    "relmse_vs_time": ("relmse", "time_s", "time (s)", "relMSE vs time"),
    "rmse_vs_spp": ("rmse", "spp", "samples per pixel", "RMSE vs samples per pixel"),
    "crop_rmse_vs_time": ("rmse_crop", "time_s", "time (s)", "crop: RMSE vs time"),
    "crop_relmse_vs_time": ("relmse_crop", "time_s", "time (s)", "crop: relMSE vs time"),
}
Y_LABELS = {"rmse": "RMSE", "relmse": "relMSE", "rmse_crop": "RMSE (crop)", "relmse_crop": "relMSE (crop)"}


def colours(labels):
    cycle = plt.get_cmap("tab10" if len(labels) <= 10 else "tab20").colors
    return {label: matplotlib.colors.to_hex(cycle[i % len(cycle)]) for i, label in enumerate(labels)}


def draw_panel(ax, panel, labels, table, colour, floor=None):
    key_y, key_x, xlabel, title = PANELS[panel]
    for label, repeats in labels.items():
        xs, med, mn, mx = band(repeats, key_x, key_y)
        if not xs:
            continue
        style = "-" if table[label]["unbiased"] else "--"
        ax.plot(xs, med, style, color=colour[label], linewidth=1.4)
        if len(repeats) > 1:
            ax.fill_between(xs, mn, mx, color=colour[label], alpha=0.18, linewidth=0)
    if floor and key_y == "rmse":
        ax.axhline(floor, color="0.4", linestyle=":", linewidth=1.2)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(Y_LABELS[key_y])
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.25)


def legend_handles(labels, table, colour, floor, repeats, slope_keys):
    """One entry per configuration with its fitted slopes (or why none), then
    what the band, the line styles and the floor mean."""
    names = {"rmse": "RMSE", "relmse": "relMSE", "rmse_crop": "RMSE", "relmse_crop": "relMSE"}
    handles = []
    for label in labels:
        t = table[label]
        if t["no_slope"]:
            note = f"no slope: {t['no_slope']}"
        else:
            note = "slope " + ", ".join(f"{names[k]} {t['slope_' + k]:+.2f}" for k in slope_keys)
        handles.append(Line2D([], [], color=colour[label], linestyle="-" if t["unbiased"] else "--",
                              label=f"{label}  ({note})"))
    if repeats > 1:
        handles.append(Patch(color="0.6", alpha=0.4, label=f"band: min–max over {repeats} repeats (line: median)"))
    handles.append(Line2D([], [], color="0.3", linestyle="--", label="dashed: biased or consistent method"))
    if floor:
        handles.append(Line2D([], [], color="0.4", linestyle=":", label=f"reference noise floor (RMSE {floor:.2g})"))
    return handles


def save(fig, stem, svg=True):
    fig.savefig(stem + ".png", dpi=110)
    if svg:
        fig.savefig(stem + ".svg")
    plt.close(fig)
    return stem + ".png"


def figure(panels, labels, table, colour, floor, repeats, slope_keys, title):
    handles = legend_handles(labels, table, colour, floor, repeats, slope_keys)
    if len(panels) == 1:  # a single panel (the files the README shows): its legend inside
        fig, ax = plt.subplots(figsize=(7, 4.5))
        draw_panel(ax, panels[0], labels, table, colour, floor)
        ax.set_title(title)
        ax.legend(handles=handles, fontsize=7, loc="best", framealpha=0.85)
        fig.tight_layout()
        return fig
    n = len(panels)
    ncol = 2 if n < 3 else 3
    legend_h = 0.19 * -(-len(handles) // ncol) + 0.1  # inches
    height = 3.2 + legend_h
    fig, axes = plt.subplots(1, n, figsize=(4.2 * n + 0.4, height), squeeze=False)
    for ax, panel in zip(axes[0], panels):
        draw_panel(ax, panel, labels, table, colour, floor)
    fig.suptitle(title, fontsize=11)
    bottom = legend_h / height
    fig.tight_layout(rect=(0, bottom, 1, 1))
    fig.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, bottom), ncol=ncol, frameon=False,
               handlelength=2.6, borderaxespad=0)
    return fig


def plot_scene(scene, labels, table, out_dir, floor=None):
    """Writes the scene's plots; returns {name: png path} for the report."""
    colour = colours(list(labels))
    repeats = max(len(r) for r in labels.values())
    stem = lambda name: os.path.join(out_dir, f"{scene}__{name}")  # noqa: E731
    files = {}
    # Single panels under their own names (the README and scripts use them).
    for panel in ("rmse_vs_time", "relmse_vs_time", "rmse_vs_spp"):
        key = PANELS[panel][0]
        fig = figure([panel], labels, table, colour, floor, repeats, [key], f"{scene}: {PANELS[panel][3]}")
        files[panel] = save(fig, stem(panel))
    fig = figure(["rmse_vs_time", "relmse_vs_time", "rmse_vs_spp"], labels, table, colour, floor, repeats,
                 ["rmse", "relmse"], f"{scene}: full frame")
    files["convergence"] = save(fig, stem("convergence"))
    if any(t["rmse_crop"] is not None for t in table.values()):
        fig = figure(["crop_rmse_vs_time", "crop_relmse_vs_time"], labels, table, colour, None, repeats,
                     ["rmse_crop", "relmse_crop"], f"{scene}: crop")
        files["crop_convergence"] = save(fig, stem("crop_convergence"))

    fig, ax = plt.subplots(figsize=(7, 0.6 + 0.28 * len(labels)))
    names = list(labels)
    ax.barh(names, [table[l]["efficiency"] for l in names], color=[colour[l] for l in names])
    ax.invert_yaxis()  # the grid's order, top to bottom
    ax.set_xscale("log")
    ax.set_xlabel("efficiency 1 / (MSE × time), mean over repeats  [higher is better]")
    ax.set_title(f"{scene}: efficiency at the final snapshot")
    ax.grid(True, axis="x", which="both", alpha=0.25)
    fig.tight_layout()
    files["efficiency"] = save(fig, stem("efficiency"))
    return files, colour
