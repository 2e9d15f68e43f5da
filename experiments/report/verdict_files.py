"""A run's verdict files, as experiments/verdict/run_folder.cpp writes them
(the one place where rank groups, intervals and tests are computed): the
report and final_table.py read them through this (lightbench.load_run reads
them into pandas).

    read_verdict(run_dir) -> {scene: SceneVerdict} or {} when the run has none

Values are in the ranked metric's own units (RMSE for rmse, relMSE for
relmse), corrected for the reference's noise; differences between pairs
are in its squared units (MSE, relMSE).
"""
import csv
import math
import os
from dataclasses import dataclass, field

METRIC_NAMES = {"rmse": "RMSE", "relmse": "relMSE", "relmse_trimmed": "relMSE trimmed",
                "rmse_crop": "crop RMSE", "relmse_crop": "crop relMSE"}


def number(text):
    """A CSV field as a float: '' is NaN, 'inf' infinity."""
    if text is None or text == "":
        return math.nan
    return float(text)


@dataclass
class SceneVerdict:
    metric: str
    rows: list = field(default_factory=list)     # verdict.csv's rows for the scene, best first
    pairs: list = field(default_factory=list)    # verdict_pairs.csv's rows
    metrics: dict = field(default_factory=dict)  # (label, metric) -> verdict_metrics.csv's row
    curves: dict = field(default_factory=dict)   # (label, metric, x) -> (xs, mean, low, high)

    def row(self, label):
        return next((r for r in self.rows if r["label"] == label), None)

    def next_pair(self, label):
        """The adjacent pair between `label` and the next one in the ranking, if any."""
        return next((p for p in self.pairs if p["adjacent"] and p["better"] == label), None)

    def undecided(self):
        return [p for p in self.pairs if p["adjacent"] and not p["decided"]]


def _read(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def read_verdict(run_dir):
    rows = _read(os.path.join(run_dir, "verdict.csv"))
    out = {}
    for r in rows:
        for k in ("value", "ci_low", "ci_high", "raw_value", "time_s", "efficiency", "efficiency_low",
                  "efficiency_high", "speedup", "speedup_low", "speedup_high", "time_to_target_s",
                  "time_to_target_low_s", "time_to_target_high_s"):
            r[k] = number(r[k])
        r["repeats"] = int(r["repeats"])
        r["decided"] = r["decided"] == "true"
        out.setdefault(r["scene"], SceneVerdict(r["metric"])).rows.append(r)
    for p in _read(os.path.join(run_dir, "verdict_pairs.csv")):
        for k in ("difference", "difference_low", "difference_high", "p", "p_holm", "reference_share"):
            p[k] = number(p[k])
        p["decided"] = p["decided"] == "true"
        p["adjacent"] = p["adjacent"] == "true"
        if p["scene"] in out:
            out[p["scene"]].pairs.append(p)
    for m in _read(os.path.join(run_dir, "verdict_metrics.csv")):
        for k in ("value", "ci_low", "ci_high", "raw_value"):
            m[k] = number(m[k])
        if m["scene"] in out:
            out[m["scene"]].metrics[(m["label"], m["metric"])] = m
    for c in _read(os.path.join(run_dir, "verdict_curves.csv")):
        if c["scene"] not in out:
            continue
        xs, mean, low, high = out[c["scene"]].curves.setdefault((c["label"], c["metric"], c["x"]), ([], [], [], []))
        xs.append(number(c["x_value"]))
        mean.append(number(c["mean"]))
        low.append(number(c["low"]))
        high.append(number(c["high"]))
    return out


def rank_text(row):
    """'1', or '2–3 (tied)' for a rank group of several ranks."""
    group = row["rank_group"]
    return group if "-" not in group else group.replace("-", "–") + " (tied)"
