#!/usr/bin/python3
"""Prints a Markdown table of an experiment's final errors: one row per scene,
one column per configuration (mean over repeats of the final RMSE), plus the
reference's own RMSE floor and the NaN/Inf count, so a run's figures can be
pasted into the README as they are.

    /usr/bin/python3 experiments/final_table.py results/extremes/<run-id> [metric]
    /usr/bin/python3 experiments/final_table.py results/caustics/<run-id> --ranked

--ranked prints one table per scene instead, as the report ranks it: rank (or
"no verdict" within 3× the reference's floor, report.py's rule), final RMSE
± its sd over repeats, and, with repeats, the bias²/variance split of
decomposition.csv.
"""
import csv
import json
import os
import sys
from collections import OrderedDict


def ranked(run_dir, floors):
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from verdict import NO_VERDICT_FACTOR
    finals = OrderedDict()
    with open(os.path.join(run_dir, "log.csv")) as f:
        for row in csv.DictReader(f):
            if row["final"] == "1":
                finals.setdefault(row["scene"], OrderedDict()).setdefault(row["label"], []).append(float(row["rmse"]))
    split = {}
    path = os.path.join(run_dir, "decomposition.csv")
    if os.path.exists(path):
        with open(path) as f:
            for r in csv.DictReader(f):
                split[(r["scene"], r["label"])] = r
    for scene, by_label in finals.items():
        floor = floors.get(scene)
        print(f"\n{scene} (reference noise floor {floor:.3g})\n" if floor else f"\n{scene}\n")
        print("| rank | configuration | final RMSE ± sd | bias² [95 %] | variance [95 %] |")
        print("|---|---|---|---|---|")
        stats = []
        for label, values in by_label.items():
            n = len(values)
            mean = sum(values) / n
            sd = (sum((v - mean) ** 2 for v in values) / (n - 1)) ** 0.5 if n > 1 else 0.0
            stats.append((mean, sd, label))
        rank = 0
        for mean, sd, label in sorted(stats):
            judged = not floor or mean >= NO_VERDICT_FACTOR * floor
            rank += judged
            d = split.get((scene, label))
            b = f"{float(d['bias2']):.2g} [{float(d['bias2_low']):.2g}, {float(d['bias2_high']):.2g}]" if d else "–"
            v = f"{float(d['variance']):.2g} [{float(d['variance_low']):.2g}, {float(d['variance_high']):.2g}]" if d else "–"
            print(f"| {rank if judged else 'no verdict'} | {label} | {mean:.3g} ± {sd:.2g} | {b} | {v} |")
    return 0


def main(argv):
    if len(argv) < 2:
        print(__doc__.strip())
        return 2
    run_dir = argv[1]
    metric = argv[2] if len(argv) > 2 else "rmse"
    floors = {}
    meta_path = os.path.join(run_dir, "meta.json")
    if os.path.exists(meta_path):
        with open(meta_path) as f:
            for s in json.load(f).get("scenes", []):
                floors[s["name"]] = s.get("reference_rmse_floor")
    if metric == "--ranked":
        return ranked(run_dir, floors)
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
            if row[metric] != "":  # e.g. crop metrics of a scene without a crop
                by_label.setdefault(row["label"], []).append(float(row[metric]))
            nonfinite[row["scene"]] = nonfinite.get(row["scene"], 0) + int(row["nonfinite"])
    print("| scene | " + " | ".join(labels) + " | reference floor | NaN/Inf |")
    print("|---" * (len(labels) + 3) + "|")
    for scene, by_label in finals.items():
        cells = []
        for label in labels:
            values = by_label.get(label)
            cells.append("%.3g" % (sum(values) / len(values)) if values else "–")
        floor = floors.get(scene)
        print("| %s | %s | %s | %d |" % (scene, " | ".join(cells), "%.3g" % floor if floor is not None else "–",
                                         nonfinite.get(scene, 0)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
