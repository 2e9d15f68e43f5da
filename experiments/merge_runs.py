#!/usr/bin/env python3
"""Merge finished run folders of one experiment into one, to judge them together.

A before/after comparison across builds (issue 33): run the same experiment
with each build against the same references (the later runs given the first
run's references as files, `reference: {file, variance, chunks}`), then

    /usr/bin/python3 experiments/merge_runs.py OUT RUN_A "after" RUN_B "before"
    ./build/lightbench verdict OUT

Each run's labels get its tag in brackets ("VCM [before]"); the log rows,
every repeat's final image, and the configurations in meta.json are merged;
the scenes, references and verdict settings are the first run's. The runs
must have the same scenes and the same references (checked byte for byte)
and equal repeats; a run folder that lacks one is refused, naming it.
Writes OUT/meta.json and OUT/log.csv (OUT must not exist), then the verdict
is the usual command's.
"""
import csv
import filecmp
import json
import os
import re
import shutil
import sys


def slug(label):
    # experiments/experiment.cpp's slug(): each byte, alphanumeric ASCII lowered, else '-'
    return "".join(chr(b).lower() if b < 128 and chr(b).isalnum() else "-" for b in label.encode())


def fail(message):
    print(f"merge_runs: {message}", file=sys.stderr)
    sys.exit(2)


def main(argv):
    if len(argv) < 5 or len(argv) % 2 == 0:
        fail("usage: merge_runs.py OUT RUN TAG RUN TAG [RUN TAG ...]")
    out, pairs = argv[0], list(zip(argv[1::2], argv[2::2]))
    if os.path.exists(out):
        fail(f"{out}: exists (the merged folder must be new)")
    metas = []
    for run, _ in pairs:
        path = os.path.join(run, "meta.json")
        if not os.path.isfile(path):
            fail(f"{path}: not found (not a finished run folder)")
        with open(path) as f:
            metas.append(json.load(f))
    first = metas[0]
    names = [s["name"] for s in first["scenes"]]
    for (run, _), meta in zip(pairs, metas):
        if [s["name"] for s in meta["scenes"]] != names:
            fail(f"{run}: scenes {[s['name'] for s in meta['scenes']]} differ from {names}")
        if meta.get("repeats") != first.get("repeats"):
            fail(f"{run}: {meta.get('repeats')} repeats, the first run {first.get('repeats')}")
        # The same reference: the same bytes, or (a given reference is written
        # anew into its run) the same noise floor measured from its variance.
        for s0, s in zip(first["scenes"], meta["scenes"]):
            for suffix in ("__reference.exr", "__reference_variance.exr"):
                a, b = os.path.join(pairs[0][0], s["name"] + suffix), os.path.join(run, s["name"] + suffix)
                if os.path.exists(a) != os.path.exists(b):
                    fail(f"{b}: present in only one of the runs")
            same = filecmp.cmp(os.path.join(pairs[0][0], s["name"] + "__reference.exr"),
                               os.path.join(run, s["name"] + "__reference.exr"), shallow=False)
            if not same and (s.get("reference_rmse_floor") is None
                             or s.get("reference_rmse_floor") != s0.get("reference_rmse_floor")
                             or s.get("reference_chunks") != s0.get("reference_chunks")):
                fail(f"{run}: scene {s['name']}'s reference is not the first run's (judged together, the runs must share it)")

    tmp = out + ".partial"
    shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(tmp)
    for name in names:
        for suffix in ("__reference.exr", "__reference_variance.exr"):
            src = os.path.join(pairs[0][0], name + suffix)
            if os.path.exists(src):
                shutil.copy(src, os.path.join(tmp, name + suffix))
    merged = dict(first)
    merged["configurations"] = []
    merged["merged_from"] = [{"run": run, "tag": tag, "git_commit": m.get("git_commit"),
                              "lightbench": m.get("lightbench")} for (run, tag), m in zip(pairs, metas)]
    rows, header = [], None
    for (run, tag), meta in zip(pairs, metas):
        relabel = {}
        for c in meta["configurations"]:
            c = dict(c)
            old = c["label"]
            c["label"] = relabel[old] = f"{old} [{tag}]"
            if isinstance(c.get("denoise"), dict) and "of" in c["denoise"]:
                c["denoise"] = dict(c["denoise"], of=f"{c['denoise']['of']} [{tag}]")
            merged["configurations"].append(c)
        with open(os.path.join(run, "log.csv"), newline="") as f:
            reader = csv.reader(f)
            h = next(reader)
            if header is None:
                header = h
            elif h != header:
                fail(f"{run}/log.csv: its columns differ from the first run's")
            li = h.index("label")
            for r in reader:
                r[li] = relabel.get(r[li], r[li])
                rows.append(r)
        for old, new in relabel.items():
            for name in names:
                stem = f"{name}__{slug(old)}"
                for fn in os.listdir(run):
                    if fn.startswith(stem) and fn.endswith(".exr") and re.fullmatch(
                            re.escape(stem) + r"(__repeat\d+)?\.exr", fn):
                        shutil.copy(os.path.join(run, fn), os.path.join(tmp, f"{name}__{slug(new)}" + fn[len(stem):]))
    labels = [c["label"] for c in merged["configurations"]]
    if len(set(labels)) != len(labels):
        fail(f"labels collide after tagging: {labels}")
    merged["verdict"] = dict(first["verdict"], baseline=labels[0])
    with open(os.path.join(tmp, "meta.json"), "w") as f:
        json.dump(merged, f, indent=2)
    with open(os.path.join(tmp, "log.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(header)
        w.writerows(rows)
    os.rename(tmp, out)
    print(f"merged {len(pairs)} runs ({len(labels)} labels) into {out}: now `lightbench verdict {out}`")


if __name__ == "__main__":
    main(sys.argv[1:])
