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

The table, the ranking and every interval come from the run's verdict
files (verdict.csv and its companions, written by the runner or by
`lightbench verdict RUN`; read by experiments/report/verdict_files.py): nothing here
tests or ranks.

Per scene it draws (SCENE__NAME.{png,svg}, experiments/report/plots.py)
  * convergence: RMSE and relMSE vs time and RMSE vs samples per pixel, one
    curve per configuration, the mean over repeats of the error corrected for
    the reference's noise with its confidence band, and for unbiased methods
    the least-squares slope of log error on log time (about -0.5 for RMSE, -1
    for relMSE); the panels also on their own (rmse_vs_time, relmse_vs_time,
    rmse_vs_spp);
  * crop_convergence: the same against time for the scene's crop, if it has one;
  * efficiency 1 / (error x time) at the final snapshot (Veach 1997, section 2.4);
  * per parameter sweep (meta.json's configurations[].sweep), its final RMSE
    against the swept value (sweep-GROUP); its members share a colour family
    in every plot and stand together under the group's name in the legends.
"""
import csv
import html
import json
import math
import os
import shutil
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "report"))

from verdict_files import METRIC_NAMES, rank_text, read_verdict  # noqa: E402
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


def fmt(v):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "—"
    if math.isinf(v):
        return "∞"
    return f"{v:.3g}"


def verdict_settings(meta):
    v = (meta or {}).get("verdict") or {}
    return v.get("confidence", 0.95), v.get("looks", 1)


def scene_notes(scene_meta, verdict, table, meta):
    """The reference line, what the ranking is and what it decided: the best
    configuration's rank group and every adjacent pair still undecided, with
    why (verdict_pairs.csv's reason)."""
    ref = page.describe_reference(scene_meta.get("reference_integrator"))
    used = scene_meta.get("reference_used", "")
    floor = scene_meta.get("reference_rmse_floor")
    floor_text = (f" Its own noise (√ of its mean per-pixel variance of the mean) is {floor:.3g} RMSE: every "
                  "measured MSE includes its square, so the errors below are <b>corrected</b> for it (each squared "
                  "term less the reference's variance there), estimating the error against the true image; "
                  "the intervals include the correction's own uncertainty." if floor else
                  " Its variance is unknown (a given EXR): errors are not corrected for its noise.")
    out = [f"<p>Reference: {esc(ref)}" + (f" ({esc(used)})" if used else "") + f".{floor_text}</p>"]
    if verdict is None:
        out.append("<p class='warn'>No verdict files in this run folder (a run from before issue 32, or a log "
                   "alone): the table is sorted by the raw final RMSE and ranks nothing. <code>lightbench verdict "
                   "RUN</code> writes them.</p>")
    else:
        confidence, looks = verdict_settings(meta)
        name = METRIC_NAMES.get(verdict.metric, verdict.metric)
        level = (f"{100 * confidence:g} % family-wise over every pair of configurations (Holm)"
                 + (f", the level split among the run's {looks} looks (Bonferroni)" if looks > 1 else ""))
        best = verdict.rows[0]
        tied = [r["label"] for r in verdict.rows if r["rank_group"].split("-")[0] == "1"]
        if best["decided"]:
            best_text = f"Best: <b>{esc(best['label'])}</b>, rank 1 decided."
        else:
            best_text = (f"Best: {esc(best['label'])}, in rank group {esc(rank_text(best))} with "
                         + esc(", ".join(l for l in tied if l != best["label"]) or "others") + ".")
        out.append(f"<p>Ranked by <b>{esc(name)}</b>, corrected; rank groups at {level}. {best_text}</p>")
        undecided = verdict.undecided()
        if undecided:
            items = "".join(f"<li>{esc(p['better'])} vs {esc(p['worse'])} ({p['repeats_better']} and "
                            f"{p['repeats_worse']} repeats, Holm p = {fmt(p['p_holm'])}): {esc(p['reason'])}</li>"
                            for p in undecided)
            out.append(f"<div class='warn'><b>Undecided neighbours</b> (tied in the ranking):<ul>{items}</ul></div>")
    # A last pass always ends a little after the budget; only an overrun
    # above 1 % of the run's time makes the comparison unequal.
    over = {l: t["over_budget"] for l, t in table.items() if t["over_budget"] > 0.01 * t["time"]}
    if over:
        out.append("<p class='warn'><b>Over budget</b> (not an equal-time comparison for these; the table's last "
                   "column): " + esc(", ".join(f"{l} by {v:.3g} s" for l, v in sorted(over.items()))) + ".</p>")
    return "".join(out)


def convergence_caption(repeats, floor, crop=None, verdict=None, confidence=0.95):
    if verdict is not None:
        band = (f"Lines: the mean over the {repeats} repeats of the error corrected for the reference's noise "
                f"(where positive); shaded bands: its {100 * confidence:g} % confidence interval (Student t over "
                "the repeats: the runs' spread, not the reference's). " if repeats > 1 else
                "Lines: the error corrected for the reference's noise (one repeat: no band). ")
    else:
        band = ("Lines: the median of the raw errors over the repeats (no verdict files: no bands). ")
    text = (band + "Dashed: biased or consistent methods, for which no slope is fitted (there is no −0.5 to "
            "compare with); nor is one where preprocessing takes more than half the final time. Slope: "
            "least-squares fit of log error on log time over every snapshot of every repeat (corrected errors); "
            "an unbiased method's RMSE falls as time<sup>−0.5</sup> and its relMSE as time<sup>−1</sup>. Time "
            "includes preprocessing.")
    if crop:
        return (f"Crop [{crop[0]}, {crop[2]}) × [{crop[1]}, {crop[3]}) only. " + text)
    if floor:
        text += f" Dotted: the reference's noise floor ({floor:.3g} RMSE); corrected errors can fall below it."
    return text


def sweep_caption(group, members, repeats):
    keys = list(members[0][1])
    values = list(dict.fromkeys(value_text(v[keys[0]]) for _, v in members))
    lines = (f"; one line per value of {esc(', '.join(keys[1:]))}" if len(keys) > 1 else "")
    faint = "; faint lines: each repeat on its own, the members sharing the repeats' seeds" if len(keys) == 1 else ""
    spread = (f"corrected, with its confidence interval over the {repeats} repeats{faint}" if repeats > 1
              else "one repeat")
    return (f"Sweep <b>{esc(group)}</b>: {len(members)} configurations. Final RMSE, {spread}, against "
            f"{esc(keys[0])} ({esc(', '.join(values))}){lines}. In the other plots its members share one colour "
            "family, lighter to darker in the experiment's order, and stand under its name in the legend.")


def write_report(run_dir, grouped, meta):
    parts = [page.head(meta.get("experiment", "")), page.run_header(meta)]
    scenes_meta = {s["name"]: s for s in meta.get("scenes", [])}
    decomposition = read_decomposition(run_dir)
    verdicts = read_verdict(run_dir)
    confidence, _ = verdict_settings(meta)
    chosen = meta.get("metrics") or ["rmse", "relmse", "mape", "variance"]
    files = {}
    # The experiment's order, whatever order parallel runs logged in: the
    # grid's rows, the plots' colours and legends follow it.
    order = {c.get("label"): i for i, c in enumerate(meta.get("configurations", []))}
    for index, (scene, labels) in enumerate(grouped.items()):
        labels = dict(sorted(labels.items(), key=lambda kv: order.get(kv[0], len(order))))
        sm = scenes_meta.get(scene, {})
        floor = sm.get("reference_rmse_floor")
        table = summary(labels, meta)
        verdict = verdicts.get(scene)
        sweeps = sweep_members(labels, meta)
        plots, colour = plot_scene(scene, labels, table, run_dir, floor, sweeps, verdict, confidence)
        files[scene] = plots
        repeats = max(len(r) for r in labels.values())
        slugs = {l: slug(l) for l in labels}
        parts += [f"<h2>{esc(scene)}</h2>", scene_notes(sm, verdict, table, meta)]

        grid = page.image_grid(run_dir, scene, labels, slugs, table, colour, sm, verdict)
        parts.append("<h3>Final images</h3>" + grid if grid else
                     "<p class='caption'>No images in this run folder (only the log).</p>")
        payload, vnotes = images.viewer_payload(run_dir, scene, labels, slugs, sm, meta) if grid else (None, [])
        if payload:
            parts += ["<h3>Viewer</h3>", page.viewer_block(index, payload, vnotes)]

        parts.append("<h3>Error against time</h3>")
        parts.append(page.plot_figure(plots["convergence"], convergence_caption(repeats, floor, None, verdict,
                                                                                  confidence)))
        if "crop_convergence" in plots:
            caption = convergence_caption(repeats, None, sm.get("crop"), verdict, confidence)
            parts.append(page.plot_figure(plots["crop_convergence"], caption))
        if sweeps:
            parts.append("<h3>Parameter sweeps</h3><div class='sweeps'>" + "".join(
                page.plot_figure(plots["sweeps"][g], sweep_caption(g, m, repeats)) for g, m in sweeps.items())
                + "</div>")

        # The experiment's `metrics` list chooses the metric columns beside
        # the ranked one (crop metrics where the scene has a crop).
        parts.append("<h3>Final snapshot</h3>")
        parts.append(page.ranking_table(table, verdict, chosen, has_crop(labels), meta))
        parts.append(page.ranking_caption(verdict, meta))
        if decomposition.get(scene):
            parts.append(page.decomposition_table(decomposition[scene]))
        parts.append(page.plot_figure(plots["efficiency"], "Efficiency 1/(error·time) at the final snapshot "
                                      "(Veach 1997, section 2.4), the error the ranked metric corrected, with its "
                                      "interval; log scale. A bar without an upper end: its corrected error may be "
                                      "0." if verdict else "Efficiency 1/(MSE·time) at the final snapshot, mean "
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
        plots = {scene: plot_scene(scene, labels, summary(labels), run_dir)[0] for scene, labels in grouped.items()}
    # The first scene's RMSE-vs-time plot also goes under a fixed name.
    first = next(iter(plots.values()))
    shutil.copyfile(first["rmse_vs_time"], os.path.join(run_dir, "rmse_vs_time.png"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
