#!/usr/bin/python3
"""Markdown tables of an experiment run's final errors, for docs/results.md.

    /usr/bin/python3 experiments/final_table.py results/caustics/<run-id> [metric]
    /usr/bin/python3 experiments/final_table.py results/caustics/<run-id> --ranked

With a metric (rmse, relmse, relmse_trimmed, rmse_crop, relmse_crop; default
rmse): one row per scene, one column per configuration, its value corrected
for the reference's noise (verdict_metrics.csv), plus the reference's own
RMSE floor and the NaN/Inf count. Other log columns (mape, variance, ...)
are the raw mean over the repeats.

--ranked: one table per scene as the verdict ranks it (verdict.csv, written
by the runner or `lightbench verdict RUN`): rank group, value and interval
of the ranked metric, Holm's p against the next row, the other corrected
metrics, the speed-up over the baseline, and the bias²/variance split of
decomposition.csv where the run has repeats. Nothing is computed here.
"""
import csv
import json
import math
import os
import sys
from collections import OrderedDict

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "report"))
from verdict_files import METRIC_NAMES, rank_text, read_verdict  # noqa: E402


def g(v, digits=3):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "–"
    if math.isinf(v):
        return "∞"
    return f"{v:.{digits}g}"


def ranked(run_dir, floors, meta):
    verdicts = read_verdict(run_dir)
    if not verdicts:
        print(f"{run_dir}: no verdict files (run `lightbench verdict {run_dir}`)", file=sys.stderr)
        return 1
    split = {}
    path = os.path.join(run_dir, "decomposition.csv")
    if os.path.exists(path):
        with open(path) as f:
            for r in csv.DictReader(f):
                split[(r["scene"], r["label"])] = r
    settings = meta.get("verdict") or {}
    for scene, v in verdicts.items():
        name = METRIC_NAMES.get(v.metric, v.metric)
        floor = floors.get(scene)
        others = [m for m in ("relmse", "relmse_trimmed", "rmse", "rmse_crop", "relmse_crop")
                  if m != v.metric and any(k[1] == m for k in v.metrics)]
        print(f"\n{scene}: ranked by {name}, corrected for the reference's noise"
              + (f" (its floor {floor:.3g} RMSE)" if floor else "")
              + f"; {100 * settings.get('confidence', 0.95):g} % family-wise"
              + (f", {settings['looks']} looks" if settings.get("looks", 1) > 1 else "") + "\n")
        print(f"| rank | configuration | {name} [interval] | vs next (Holm p) | "
              + " | ".join(METRIC_NAMES[m] for m in others)
              + f" | speed-up over {v.rows[0]['baseline']} | repeats | bias² | variance |")
        print("|---" * (8 + len(others)) + "|")
        for r in v.rows:
            pair = v.next_pair(r["label"])
            nxt = f"{g(pair['p_holm'], 2)}{'' if pair['decided'] else ' (tied)'}" if pair else ""
            cells = [g(v.metrics[(r["label"], m)]["value"]) if (r["label"], m) in v.metrics else "–" for m in others]
            d = split.get((scene, r["label"]))
            b = f"{float(d['bias2']):.2g} [{float(d['bias2_low']):.2g}, {float(d['bias2_high']):.2g}]" if d else "–"
            var = f"{float(d['variance']):.2g}" if d else "–"
            print(f"| {rank_text(r)} | {r['label']} | {g(r['value'])} [{g(r['ci_low'])}, {g(r['ci_high'])}] | {nxt} | "
                  + " | ".join(cells)
                  + f" | {g(r['speedup'])} [{g(r['speedup_low'])}, {g(r['speedup_high'])}] | {r['repeats']} | {b} | {var} |")
        undecided = v.undecided()
        if undecided:
            print()
            for p in undecided:
                print(f"- undecided: {p['better']} vs {p['worse']}: {p['reason']}")
    return 0


def main(argv):
    if len(argv) < 2:
        print(__doc__.strip())
        return 2
    run_dir = argv[1]
    metric = argv[2] if len(argv) > 2 else "rmse"
    floors, meta = {}, {}
    meta_path = os.path.join(run_dir, "meta.json")
    if os.path.exists(meta_path):
        with open(meta_path) as f:
            meta = json.load(f)
        for s in meta.get("scenes", []):
            floors[s["name"]] = s.get("reference_rmse_floor")
    if metric == "--ranked":
        return ranked(run_dir, floors, meta)
    verdicts = read_verdict(run_dir)
    finals = OrderedDict()
    labels = []
    nonfinite = {}
    with open(os.path.join(run_dir, "log.csv")) as f:
        for row in csv.DictReader(f):
            if row["final"] != "1":
                continue
            if row["label"] not in labels:
                labels.append(row["label"])
            by_label = finals.setdefault(row["scene"], {})
            if row.get(metric, "") != "":  # e.g. crop metrics of a scene without a crop
                by_label.setdefault(row["label"], []).append(float(row[metric]))
            nonfinite[row["scene"]] = nonfinite.get(row["scene"], 0) + int(row["nonfinite"])
    corrected = metric in METRIC_NAMES and verdicts
    print(f"({metric}: {'corrected for the reference' if corrected else 'raw, mean over the repeats'})\n")
    print("| scene | " + " | ".join(labels) + " | reference floor | NaN/Inf |")
    print("|---" * (len(labels) + 3) + "|")
    for scene, by_label in finals.items():
        cells = []
        for label in labels:
            if corrected:
                m = verdicts.get(scene) and verdicts[scene].metrics.get((label, metric))
                cells.append(g(m["value"]) if m else "–")
            else:
                values = by_label.get(label)
                cells.append(g(sum(values) / len(values)) if values else "–")
        floor = floors.get(scene)
        print("| %s | %s | %s | %d |" % (scene, " | ".join(cells), g(floor) if floor is not None else "–",
                                         nonfinite.get(scene, 0)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
