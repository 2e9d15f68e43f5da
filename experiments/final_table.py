#!/usr/bin/python3
"""Prints a Markdown table of an experiment's final errors: one row per scene,
one column per configuration (mean over repeats of the final RMSE), plus the
reference's own RMSE floor and the NaN/Inf count, so a run's figures can be
pasted into the README as they are.

    /usr/bin/python3 experiments/final_table.py results/extremes/<run-id> [metric]
"""
import csv
import json
import os
import sys
from collections import OrderedDict


def main(argv):
    if len(argv) < 2:
        print(__doc__.strip())
        return 2
    run_dir = argv[1]
    metric = argv[2] if len(argv) > 2 else "rmse"
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
    floors = {}
    meta_path = os.path.join(run_dir, "meta.json")
    if os.path.exists(meta_path):
        with open(meta_path) as f:
            for s in json.load(f).get("scenes", []):
                floors[s["name"]] = s.get("reference_rmse_floor")
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
