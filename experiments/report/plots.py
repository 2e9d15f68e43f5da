"""The report's plots (matplotlib, Agg): error against time and samples, the
crop's error against time, efficiency at the final snapshot, and per
parameter sweep its final error against the swept value.

One colour per configuration across every plot and the image grid; unbiased
configurations are drawn solid, biased or consistent ones dashed. Each curve
is the mean over repeats of the error corrected for the reference's noise,
and its shaded band the confidence interval of that mean (the run's verdict
files, experiments/report/verdict_files.py: Student t over the repeats, the runs' spread);
a run without them shows the median of the raw errors, with no band. The
members of a sweep share one colour family (a sequential colormap, lighter to
darker in the experiment's order) and stand together in the legends under
their group's name, so that a sweep reads as one thing among the others.
"""
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import ticker  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from runlog import band, member_name, slug  # noqa: E402

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


# A sweep's colour family: a sequential colormap, and the tab10 hue it
# resembles, which ordinary configurations then leave to it.
SWEEP_FAMILIES = [("Blues", 0), ("Oranges", 1), ("Greens", 2), ("Reds", 3), ("Purples", 4), ("Greys", 7)]


def sweep_colormaps(groups):
    """{group: colormap name}, the families in turn (they repeat past six groups)."""
    return {g: SWEEP_FAMILIES[i % len(SWEEP_FAMILIES)][0] for i, g in enumerate(dict.fromkeys(groups))}


def member_shade(i, n):
    """Where member i of n sits on its colormap: 0.45 to 0.95, since the
    light end of a sequential map is too pale to see on white."""
    return 0.45 + 0.5 * i / (n - 1) if n > 1 else 0.7


def assign_colours(labels, group_of=None):
    """{label: hex colour} for labels in the experiment's order; group_of maps
    a sweep member's label to its group (ordinary configurations are absent).
    Ordinary configurations take tab10's colours in turn, skipping the hues of
    the sweeps' families (then tab20's lighter shades of the same hues); the
    members of a sweep take shades of their group's colormap by member index.
    Without sweeps this is tab10 in order, as before sweeps existed."""
    group_of = group_of or {}
    maps = sweep_colormaps(group_of[l] for l in labels if l in group_of)
    claimed = {hue for name, hue in SWEEP_FAMILIES if name in maps.values()}
    tab10, tab20 = plt.get_cmap("tab10").colors, plt.get_cmap("tab20").colors
    free = [i for i in range(10) if i not in claimed]
    pool = [tab10[i] for i in free] + [tab20[2 * i + 1] for i in free]
    out = {}
    plain = [l for l in labels if l not in group_of]
    for i, label in enumerate(plain):
        out[label] = matplotlib.colors.to_hex(pool[i % len(pool)])
    for group, name in maps.items():
        members = [l for l in labels if group_of.get(l) == group]
        cmap = plt.get_cmap(name)
        for i, label in enumerate(members):
            out[label] = matplotlib.colors.to_hex(cmap(member_shade(i, len(members))))
    return out


class PlainLogFormatter(ticker.LogFormatter):
    """LogFormatter's choice of which ticks to label, written as plain numbers
    (0.3, 2, 1e-05): its own text is 3e-01, and the default formatter's
    3×10⁻¹ under every minor tick of a short axis overlaps its neighbours."""

    def __call__(self, x, pos=None):
        return f"{x:g}" if super().__call__(x, pos) else ""


def log_axis_labels(axis):
    """Minor ticks labelled too where the axis spans under two decades (all
    of them under half a decade), so that a short axis has numbers on it."""
    axis.set_major_formatter(PlainLogFormatter(labelOnlyBase=False))
    axis.set_minor_formatter(PlainLogFormatter(labelOnlyBase=False, minor_thresholds=(2, 0.5)))


def draw_panel(ax, panel, labels, table, colour, floor=None, verdict=None):
    key_y, key_x, xlabel, title = PANELS[panel]
    lowest = math.inf
    bands = []
    for label, repeats in labels.items():
        style = "-" if table[label]["unbiased"] else "--"
        curve = verdict.curves.get((label, key_y, key_x)) if verdict else None
        if curve:
            xs, mean, low, high = curve
            shown = [(x, m, lo, hi) for x, m, lo, hi in zip(xs, mean, low, high) if m > 0]
            if not shown:
                continue
            xs, mean, low, high = (list(c) for c in zip(*shown))
            ax.plot(xs, mean, style, color=colour[label], linewidth=1.4)
            lowest = min(lowest, min(mean))
            if len(repeats) > 1:
                bands.append((xs, low, high, colour[label]))
            continue
        xs, med, _, _ = band(repeats, key_x, key_y)
        if xs:
            ax.plot(xs, med, style, color=colour[label], linewidth=1.4)
            lowest = min([lowest] + [v for v in med if v > 0])
    # A band whose lower edge is not positive (a corrected error that could
    # be 0) reaches the bottom of the axis.
    bottom = lowest / 4 if math.isfinite(lowest) else None
    for xs, low, high, c in bands:
        ax.fill_between(xs, [lo if lo > 0 else bottom for lo in low], high, color=c, alpha=0.18, linewidth=0)
    if bottom:
        ax.set_ylim(bottom=bottom)
    if floor and key_y == "rmse":
        ax.axhline(floor, color="0.4", linestyle=":", linewidth=1.2)
    ax.set_xscale("log")
    ax.set_yscale("log")
    log_axis_labels(ax.xaxis)
    log_axis_labels(ax.yaxis)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(Y_LABELS[key_y])
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.25)


def legend_blocks(labels, table, colour, floor, repeats, slope_keys, sweeps=None, confidence=None):
    """The legend as blocks of entries: an ordinary configuration is a block
    of one; a sweep is a block headed by its group's name (a header entry
    with no line, gid "sweep-group") with its members under it, named by
    their values; then what the band, the line styles and the floor mean.
    Each configuration's entry states its fitted slopes, or why none."""
    names = {"rmse": "RMSE", "relmse": "relMSE", "rmse_crop": "RMSE", "relmse_crop": "relMSE"}
    group_of = {l: g for g, members in (sweeps or {}).items() for l, _ in members}

    def entry(label, text):
        t = table[label]
        if t["no_slope"]:
            note = f"no slope: {t['no_slope']}"
        else:
            note = "slope " + ", ".join(f"{names[k]} {t['slope_' + k]:+.2f}" for k in slope_keys)
        return Line2D([], [], color=colour[label], linestyle="-" if t["unbiased"] else "--", label=f"{text}  ({note})")

    blocks, done = [], set()
    for label in labels:
        group = group_of.get(label)
        if group is None:
            blocks.append([entry(label, label)])
        elif group not in done:
            done.add(group)
            members = [l for l, _ in sweeps[group] if l in labels]
            keys = list(sweeps[group][0][1])
            header = Line2D([], [], linestyle="none", label=f"{group}: sweep over {', '.join(keys)}")
            header.set_gid("sweep-group")
            blocks.append([header] + [entry(l, member_name(l, group)) for l in members])
    notes = []
    if repeats > 1 and confidence:
        notes.append(Patch(color="0.6", alpha=0.4, label=f"band: {100 * confidence:g} % interval of the mean over "
                           f"{repeats} repeats (line: the mean, corrected)"))
    notes.append(Line2D([], [], color="0.3", linestyle="--", label="dashed: biased or consistent method"))
    if floor:
        notes.append(Line2D([], [], color="0.4", linestyle=":", label=f"reference noise floor (RMSE {floor:.2g})"))
    return blocks + [[n] for n in notes]


def pack_legend(blocks, ncol):
    """The entries in the order matplotlib's legend lays them out (down each
    column, then the next), padded with blank entries so that no sweep is
    split between columns where it fits in one. Returns (handles, rows)."""
    blank = lambda: Line2D([], [], linestyle="none", label=" ")  # noqa: E731
    total = sum(len(b) for b in blocks)
    fewest = max(1, -(-total // ncol))
    # Tall enough for the longest sweep, unless that would take over twelve
    # rows beyond what the entries need: a long sweep may wrap.
    start = max(fewest, min(max(len(b) for b in blocks), max(fewest, 12)))
    for rows in range(start, total + 1):
        columns = [[]]
        for b in blocks:
            if len(b) <= rows and len(columns[-1]) + len(b) > rows:
                columns.append([])  # start the block at the top of the next column
            for h in b:
                if len(columns[-1]) == rows:
                    columns.append([])
                columns[-1].append(h)
        if len(columns) <= ncol:
            break
    # matplotlib fills columns of equal height only when every column is full.
    handles = [h for c in columns for h in c + [blank() for _ in range(rows - len(c))]]
    handles += [blank() for _ in range(rows * ncol - len(handles))]
    return handles, rows


def bold_headers(legend, handles):
    for h, text in zip(handles, legend.get_texts()):
        if h.get_gid() == "sweep-group":
            text.set_fontweight("bold")


def save(fig, stem, svg=True):
    fig.savefig(stem + ".png", dpi=110)
    if svg:
        fig.savefig(stem + ".svg")
    plt.close(fig)
    return stem + ".png"


def figure(panels, labels, table, colour, floor, repeats, slope_keys, title, sweeps=None, verdict=None,
           confidence=None):
    blocks = legend_blocks(labels, table, colour, floor, repeats, slope_keys, sweeps, confidence if verdict else None)
    if len(panels) == 1:  # a single panel (the files the README shows): its legend inside
        fig, ax = plt.subplots(figsize=(7, 4.5))
        draw_panel(ax, panels[0], labels, table, colour, floor, verdict)
        ax.set_title(title)
        handles = [h for b in blocks for h in b]
        bold_headers(ax.legend(handles=handles, fontsize=7, loc="best", framealpha=0.85), handles)
        fig.tight_layout()
        return fig
    n = len(panels)
    ncol = 2 if n < 3 else 3
    handles, rows = pack_legend(blocks, ncol)
    legend_h = 0.19 * rows + 0.1  # inches
    height = 3.2 + legend_h
    fig, axes = plt.subplots(1, n, figsize=(4.2 * n + 0.4, height), squeeze=False)
    for ax, panel in zip(axes[0], panels):
        draw_panel(ax, panel, labels, table, colour, floor, verdict)
    fig.suptitle(title, fontsize=11)
    bottom = legend_h / height
    fig.tight_layout(rect=(0, bottom, 1, 1))
    legend = fig.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, bottom), ncol=ncol, frameon=False,
                        handlelength=2.6, borderaxespad=0)
    bold_headers(legend, handles)
    return fig


def sweep_points(members, labels, verdict=None):
    """Per member: (values, value, low, high, {repeat: final}) of the final
    RMSE: the verdict's corrected value and interval when the run has them,
    else the mean, min and max of the raw values over the repeats."""
    out = []
    for label, values in members:
        finals = {rep: rows[-1]["rmse"] for rep, rows in labels.get(label, {}).items() if rows}
        if not finals:
            continue
        m = verdict.metrics.get((label, "rmse")) if verdict else None
        if m:
            out.append((values, m["value"], m["ci_low"], m["ci_high"], finals))
        else:
            v = list(finals.values())
            out.append((values, sum(v) / len(v), min(v), max(v), finals))
    return out


def is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def value_text(v):
    """A swept value as the experiment file writes it (true, 0.01, power)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    return f"{v:g}" if isinstance(v, float) else str(v)


def plot_sweep(ax, scene, group, members, labels, colour, cmap_name, floor=None, verdict=None):
    """Final RMSE against the first swept key: one line, or with more keys one
    line per combination of the others (with two keys: per value of the
    last). Error bars: the verdict's confidence interval (corrected values),
    or min-max over the repeats without verdict files. Log x where every
    value is positive and they span over 10x; keys with text values are
    categories."""
    points = sweep_points(members, labels, verdict)
    ax.set_title(f"{scene}: sweep {group}")
    if not points:
        ax.text(0.5, 0.5, "no final snapshots", ha="center", va="center", transform=ax.transAxes)
        return
    keys = list(members[0][1])
    first, rest = keys[0], keys[1:]
    xs_all = list(dict.fromkeys(v[first] for v, *_ in points))
    numeric = all(is_number(x) for x in xs_all)
    logx = numeric and all(x > 0 for x in xs_all) and max(xs_all) > 10 * min(xs_all)
    position = (lambda x: x) if numeric else {x: i for i, x in enumerate(xs_all)}.get
    lines = list(dict.fromkeys(tuple(v[k] for k in rest) for v, *_ in points))
    cmap = plt.get_cmap(cmap_name)
    markers = "osD^vP*X"
    for j, line in enumerate(lines):
        pts = sorted((p for p in points if tuple(p[0][k] for k in rest) == line),
                     key=lambda p: position(p[0][first]) if numeric else xs_all.index(p[0][first]))
        # Lines side by side at a shared x: a small offset keeps their error bars apart.
        off = (j - (len(lines) - 1) / 2) * 0.02
        xs = [position(p[0][first]) for p in pts]
        xs = [x * math.exp(off) if logx else x + off * ((max(xs_all) - min(xs_all)) if numeric else 4) for x in xs]
        means = [p[1] for p in pts]
        err = [[p[1] - p[2] for p in pts], [p[3] - p[1] for p in pts]]
        name = ", ".join(f"{k}={value_text(v)}" for k, v in zip(rest, line)) if rest else None
        line_colour = cmap(member_shade(j, len(lines)) if rest else 0.85)
        ax.errorbar(xs, means, yerr=err, color=line_colour, marker=markers[j % len(markers)], markersize=6,
                    linewidth=1.4, capsize=3, label=name)
        # Each repeat on its own, faint (one line only: more would crowd it).
        # Every member runs with the same seeds, so a spread that they all
        # share (one repeat's luck) can hide no trend the repeats agree on.
        for rep in sorted({r for p in pts for r in p[4]}) if not rest else []:
            ys = [(x, p[4][rep]) for x, p in zip(xs, pts) if rep in p[4]]
            if len(ys) > 1:
                ax.plot(*zip(*ys), color=line_colour, linewidth=0.7, alpha=0.35, marker=".", markersize=3)
        if not rest:  # one line: each point in its member's colour, as in the other plots
            member_of = {tuple(v.items()): l for l, v in members}
            for x, p in zip(xs, pts):
                ax.plot([x], [p[1]], marker="o", markersize=6, linestyle="none",
                        color=colour[member_of[tuple(p[0].items())]], markeredgecolor=line_colour, zorder=3)
    if logx:
        ax.set_xscale("log")
    if numeric:  # ticks at the swept values, written as the experiment file has them
        ax.set_xticks(xs_all, minor=False)
        ax.xaxis.set_major_formatter(ticker.FuncFormatter(lambda v, _: value_text(float(v))))
        ax.xaxis.set_minor_formatter(ticker.NullFormatter())
    else:
        ax.set_xticks(range(len(xs_all)), [value_text(x) for x in xs_all])
    lo, hi = ax.get_ylim()
    if floor and lo <= floor <= hi:  # only where it does not squash the points
        ax.axhline(floor, color="0.4", linestyle=":", linewidth=1.2, label=f"reference noise floor ({floor:.2g})")
    ax.set_xlabel(first)
    ax.set_ylabel("final RMSE")
    ax.grid(True, which="both", alpha=0.25)
    handles, names = ax.get_legend_handles_labels()
    if handles:  # the lines first, the floor (drawn last, listed first by matplotlib) after them
        order = sorted(range(len(names)), key=lambda i: names[i].startswith("reference noise floor"))
        ax.legend([handles[i] for i in order], [names[i] for i in order], fontsize=7,
                  title=", ".join(rest) if rest else None, title_fontsize=7, framealpha=0.85)


def plot_scene(scene, labels, table, out_dir, floor=None, sweeps=None, verdict=None, confidence=None):
    """Writes the scene's plots; returns ({name: png path}, {label: colour})
    for the report. sweeps: runlog.sweep_members(); with sweeps, files has
    "sweeps": {group: png path} (one small plot per sweep). verdict: the
    scene's verdict.SceneVerdict (its mean curves and intervals), or None."""
    sweeps = sweeps or {}
    group_of = {l: g for g, members in sweeps.items() for l, _ in members}
    colour = assign_colours(list(labels), group_of)
    repeats = max(len(r) for r in labels.values())
    stem = lambda name: os.path.join(out_dir, f"{scene}__{name}")  # noqa: E731
    files = {}
    # Single panels under their own names (the README and scripts use them).
    for panel in ("rmse_vs_time", "relmse_vs_time", "rmse_vs_spp"):
        key = PANELS[panel][0]
        fig = figure([panel], labels, table, colour, floor, repeats, [key], f"{scene}: {PANELS[panel][3]}", sweeps,
                     verdict, confidence)
        files[panel] = save(fig, stem(panel))
    fig = figure(["rmse_vs_time", "relmse_vs_time", "rmse_vs_spp"], labels, table, colour, floor, repeats,
                 ["rmse", "relmse"], f"{scene}: full frame", sweeps, verdict, confidence)
    files["convergence"] = save(fig, stem("convergence"))
    if any(t["rmse_crop"] is not None for t in table.values()):
        fig = figure(["crop_rmse_vs_time", "crop_relmse_vs_time"], labels, table, colour, None, repeats,
                     ["rmse_crop", "relmse_crop"], f"{scene}: crop", sweeps, verdict, confidence)
        files["crop_convergence"] = save(fig, stem("crop_convergence"))

    fig, ax = plt.subplots(figsize=(7, 0.6 + 0.28 * len(labels)))
    names = list(labels)
    rows = {l: verdict.row(l) if verdict else None for l in names}
    if verdict and all(rows.values()):
        # 1 / (the ranked metric × time), with the interval the metric's gives.
        values = [rows[l]["efficiency"] for l in names]
        finite = [v for v in values if math.isfinite(v)]
        cap = 10 * max(finite) if finite else 1
        values = [v if math.isfinite(v) else cap for v in values]
        lo = [max(0.0, v - rows[l]["efficiency_low"]) for v, l in zip(values, names)]
        hi = [max(0.0, min(rows[l]["efficiency_high"], cap) - v) for v, l in zip(values, names)]
        ax.barh(names, values, xerr=[lo, hi], color=[colour[l] for l in names], ecolor="0.25", capsize=2)
        unit = "MSE" if verdict.metric.startswith("rmse") else "relMSE"
        xlabel = (f"efficiency 1 / ({unit} × time), corrected, with its {100 * (confidence or 0.95):g} % interval  "
                  "[higher is better]")
    else:
        ax.barh(names, [table[l]["efficiency"] for l in names], color=[colour[l] for l in names])
        xlabel = "efficiency 1 / (MSE × time), mean over repeats  [higher is better]"
    ax.invert_yaxis()  # the grid's order, top to bottom
    ax.set_xscale("log")
    log_axis_labels(ax.xaxis)
    ax.set_xlabel(xlabel)
    ax.set_title(f"{scene}: efficiency at the final snapshot")
    ax.grid(True, axis="x", which="both", alpha=0.25)
    fig.tight_layout()
    files["efficiency"] = save(fig, stem("efficiency"))

    maps = sweep_colormaps(sweeps)
    for group, members in sweeps.items():
        fig, ax = plt.subplots(figsize=(4.6, 3.3))
        plot_sweep(ax, scene, group, members, labels, colour, maps[group], floor, verdict)
        fig.tight_layout()
        files.setdefault("sweeps", {})[group] = save(fig, stem("sweep-" + slug(group)))
    return files, colour
