#!/usr/bin/python3
"""Plots and an HTML report for one experiment run.

    /usr/bin/python3 experiments/report.py results/NAME/RUN-ID[/log.csv] [--mixed-machines]

Runs of one scene timed on different kinds of machine (the log's cpu and
threads columns: an MPI sweep over a mixed cluster) are refused (exit 3)
unless --mixed-machines is given.

Works on any log.csv (plots only); with the run's meta.json beside it, it
also writes a self-contained report.html: every image embedded, and an
interactive viewer (experiments/report/viewer.js, inlined) that flips between
the reference and the configurations with zoom, pan and exposure. Uses
Debian's python3-matplotlib and numpy; run it with /usr/bin/python3. The
viewer reads the run's EXRs through the `lightbench` Python module when it is
importable (the runner puts it on PYTHONPATH), else the 8-bit PNGs.

Per scene it draws (SCENE__NAME.{png,svg}, experiments/report/plots.py)
  * convergence: RMSE and relMSE vs time and RMSE vs samples per pixel, one
    curve per configuration, the median over repeats with the min-max band,
    and for unbiased methods the least-squares slope of log error on log time
    (about -0.5 for RMSE, -1 for relMSE); the panels also on their own
    (rmse_vs_time, relmse_vs_time, rmse_vs_spp);
  * crop_convergence: the same against time for the scene's crop, if it has one;
  * efficiency 1 / (MSE x time) at the final snapshot (Veach 1997, section 2.4);
  * per parameter sweep (meta.json's configurations[].sweep), its final RMSE
    against the swept value (sweep-GROUP); its members share a colour family
    in every plot and stand together under the group's name in the legends.
"""
import csv
import html
import json
import os
import shutil
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "report"))

from verdict import NO_VERDICT_FACTOR  # noqa: E402 (this script's folder is on sys.path)
import images  # noqa: E402
import page  # noqa: E402
from plots import plot_scene, value_text  # noqa: E402
from runlog import group, has_crop, read_log, slug, summary, sweep_members  # noqa: E402

esc = html.escape


def read_decomposition(run_dir):
    out = {}
    path = os.path.join(run_dir, "decomposition.csv")
    if os.path.exists(path):
        with open(path, newline="") as f:
            for r in csv.DictReader(f):
                out.setdefault(r["scene"], []).append(r)
    return out


def scene_notes(scene_meta, table, best):
    """The reference line, the noise-floor warning and the ranks. A final
    RMSE within NO_VERDICT_FACTOR x the reference's own noise cannot be told
    from the reference's error: such a configuration is not ranked (issue 13)."""
    ref = page.describe_reference(scene_meta.get("reference_integrator"))
    used = scene_meta.get("reference_used", "")
    floor = scene_meta.get("reference_rmse_floor")
    judged = lambda t: not floor or t["rmse"] >= NO_VERDICT_FACTOR * floor  # noqa: E731
    ranked = sorted((l for l, t in table.items() if judged(t)), key=lambda l: table[l]["rmse"])
    rank = {label: i + 1 for i, label in enumerate(ranked)}
    floor_text = (f" Its own noise (sqrt of its mean per-pixel variance) is {floor:.3g}: every measured MSE "
                  "includes its square, so RMSE cannot be seen to fall below it." if floor else "")
    best_text = (f"Best final RMSE: <b>{esc(best)}</b>." if best in rank else
                 f"Best final RMSE: {esc(best)}, within {NO_VERDICT_FACTOR:g}× the reference's noise floor: "
                 "<b>no verdict (reference too noisy)</b>.")
    out = [f"<p>Reference: {esc(ref)}" + (f" ({esc(used)})" if used else "") + f".{floor_text} {best_text}</p>"]
    close = [l for l, t in table.items() if not judged(t)]
    if close:
        out.append(
            "<div class='warn strong'><b>Reference too noisy for: " + esc(", ".join(close)) + ".</b> Their "
            "final RMSE (" + esc(", ".join(f"{table[l]['rmse']:.3g}" for l in close)) + ") is within "
            f"{NO_VERDICT_FACTOR:g}× the reference's noise floor ({floor:.3g} RMSE): the reference's own error "
            "could account for the differences, so they are not ranked (no verdict). A longer reference (a lower "
            "noise_floor in the experiment file) would settle it.</div>")
    # A last pass always ends a little after the budget; only an overrun
    # above 1 % of the run's time makes the comparison unequal.
    over = {l: t["over_budget"] for l, t in table.items() if t["over_budget"] > 0.01 * t["time"]}
    if over:
        out.append("<p class='warn'><b>Over budget</b> (not an equal-time comparison for these; the table's last "
                   "column): " + esc(", ".join(f"{l} by {v:.3g} s" for l, v in sorted(over.items()))) + ".</p>")
    return "".join(out), rank


def convergence_caption(repeats, floor, crop=None):
    band = (f"Lines: median over the {repeats} repeats; shaded bands: min–max over the repeats (their whole "
            "spread, not a confidence interval). " if repeats > 1 else "One repeat: no band. ")
    text = (band + "Dashed: biased or consistent methods, for which no slope is fitted (there is no −0.5 to "
            "compare with); nor is one where preprocessing takes more than half the final time. Slope: "
            "least-squares fit of log error on log time over every snapshot of every repeat; an unbiased "
            "method's RMSE falls as time<sup>−0.5</sup> and its relMSE as time<sup>−1</sup>. Time includes "
            "preprocessing.")
    if crop:
        return (f"Crop [{crop[0]}, {crop[2]}) × [{crop[1]}, {crop[3]}) only. " + text
                + " The reference's noise floor is known for the whole image only, so none is drawn here.")
    if floor:
        text += f" Dotted: the reference's noise floor ({floor:.3g} RMSE)."
    return text


def sweep_caption(group, members, repeats):
    keys = list(members[0][1])
    values = list(dict.fromkeys(value_text(v[keys[0]]) for _, v in members))
    lines = (f"; one line per value of {esc(', '.join(keys[1:]))}" if len(keys) > 1 else "")
    faint = "; faint lines: each repeat on its own, the members sharing the repeats' seeds" if len(keys) == 1 else ""
    spread = f"mean over the {repeats} repeats (error bars: min–max over them{faint})" if repeats > 1 else "one repeat"
    return (f"Sweep <b>{esc(group)}</b>: {len(members)} configurations. Final RMSE, {spread}, against "
            f"{esc(keys[0])} ({esc(', '.join(values))}){lines}. In the other plots its members share one colour "
            "family, lighter to darker in the experiment's order, and stand under its name in the legend.")


def write_report(run_dir, grouped, meta):
    parts = [page.head(meta.get("experiment", "")), page.run_header(meta)]
    scenes_meta = {s["name"]: s for s in meta.get("scenes", [])}
    decomposition = read_decomposition(run_dir)
    chosen = meta.get("metrics") or ["rmse", "relmse", "mape", "variance"]
    files = {}
    # The experiment's order, whatever order parallel runs logged in: the
    # grid's rows, the plots' colours and legends follow it.
    order = {c.get("label"): i for i, c in enumerate(meta.get("configurations", []))}
    for index, (scene, labels) in enumerate(grouped.items()):
        labels = dict(sorted(labels.items(), key=lambda kv: order.get(kv[0], len(order))))
        sm = scenes_meta.get(scene, {})
        floor = sm.get("reference_rmse_floor")
        table, best = summary(labels, meta)
        sweeps = sweep_members(labels, meta)
        plots, colour = plot_scene(scene, labels, table, run_dir, floor, sweeps)
        files[scene] = plots
        repeats = max(len(r) for r in labels.values())
        slugs = {l: slug(l) for l in labels}
        notes, rank = scene_notes(sm, table, best)
        parts += [f"<h2>{esc(scene)}</h2>", notes]

        grid = page.image_grid(run_dir, scene, labels, slugs, table, colour, sm)
        parts.append("<h3>Final images</h3>" + grid if grid else
                     "<p class='caption'>No images in this run folder (only the log).</p>")
        payload, vnotes = images.viewer_payload(run_dir, scene, labels, slugs, sm, meta) if grid else (None, [])
        if payload:
            parts += ["<h3>Viewer</h3>", page.viewer_block(index, payload, vnotes)]

        parts.append("<h3>Error against time</h3>")
        parts.append(page.plot_figure(plots["convergence"], convergence_caption(repeats, floor)))
        if "crop_convergence" in plots:
            caption = convergence_caption(repeats, None, sm.get("crop"))
            parts.append(page.plot_figure(plots["crop_convergence"], caption))
        if sweeps:
            parts.append("<h3>Parameter sweeps</h3><div class='sweeps'>" + "".join(
                page.plot_figure(plots["sweeps"][g], sweep_caption(g, m, repeats)) for g, m in sweeps.items())
                + "</div>")

        # The experiment's `metrics` list chooses the metric columns (RMSE is
        # always shown: the plots, time-to-best and efficiency are built on it).
        parts.append("<h3>Final snapshot</h3>")
        parts.append(page.ranking_table(table, rank, chosen, has_crop(labels)))
        parts.append("<p class='caption'>Best final RMSE first; rank only where the reference's noise allows a "
                     "verdict. Slope: of log error on log time (see the plots); none for biased or consistent "
                     "methods (b) or where preprocessing takes over half the time (p). Time to best's final RMSE: "
                     "when the median curve first reaches the best configuration's final median RMSE (—: not "
                     "within the budget). Efficiency relative to the most efficient.</p>")
        if decomposition.get(scene):
            parts.append(page.decomposition_table(decomposition[scene]))
        parts.append(page.plot_figure(plots["efficiency"], "Efficiency 1/(MSE·time) at the final snapshot, mean "
                                      "over repeats (Veach 1997, section 2.4); log scale."))
    parts.append(page.tail())
    out = os.path.join(run_dir, "report.html")
    tmp = out + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write("\n".join(parts))
    os.replace(tmp, out)
    return out, files


def machine_kinds(rows):
    """scene -> the kinds of machine its runs were timed on: (cpu, threads).
    Logs written before the columns existed have one unnamed kind."""
    kinds = {}
    for r in rows:
        kinds.setdefault(r["scene"], set()).add((r.get("cpu") or "", r.get("threads") or ""))
    return kinds


def main(argv):
    mixed = "--mixed-machines" in argv[1:]
    args = [a for a in argv[1:] if a != "--mixed-machines"]
    if len(args) != 1:
        print(__doc__, file=sys.stderr)
        return 2
    log = args[0]
    if os.path.isdir(log):
        log = os.path.join(log, "log.csv")
    run_dir = os.path.dirname(os.path.abspath(log))
    rows = read_log(log)
    # Equal-time comparisons hold only between runs timed alike (issue 19):
    # an MPI sweep over a heterogeneous cluster is refused unless asked for.
    for scene, kinds in machine_kinds(rows).items():
        if len(kinds) > 1 and not mixed:
            named = "; ".join(f"{cpu or 'unknown cpu'} with {threads or '?'} threads" for cpu, threads in sorted(kinds))
            print(f"report: {log}: runs of scene '{scene}' were timed on {len(kinds)} kinds of machine ({named}); "
                  "their times cannot be compared. Rerun on one kind, or pass --mixed-machines "
                  "(lightbench run --mixed-machines) to compare them anyway", file=sys.stderr)
            return 3
    grouped = group(rows)
    if not grouped:
        print(f"report: no complete rows in {log}", file=sys.stderr)
        return 1
    meta_path = os.path.join(run_dir, "meta.json")
    meta = None
    if os.path.exists(meta_path):
        with open(meta_path) as f:
            meta = json.load(f)
    if meta is not None:
        _, plots = write_report(run_dir, grouped, meta)
    else:
        plots = {scene: plot_scene(scene, labels, summary(labels)[0], run_dir)[0] for scene, labels in grouped.items()}
    # The first scene's RMSE-vs-time plot also goes under a fixed name.
    first = next(iter(plots.values()))
    shutil.copyfile(first["rmse_vs_time"], os.path.join(run_dir, "rmse_vs_time.png"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
