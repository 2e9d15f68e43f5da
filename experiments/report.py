#!/usr/bin/python3
"""Plots and an HTML report for one experiment run.

    /usr/bin/python3 experiments/report.py results/NAME/RUN-ID/log.csv

Works on any log.csv (plots only); with the run's meta.json and images beside
it, it also writes a self-contained report.html (images embedded). Uses
Debian's python3-matplotlib; run it with /usr/bin/python3.

Per scene it draws
  * RMSE vs time (log-log): one curve per configuration, the median over
    repeats with the min-max band, and the least-squares slope of log RMSE on
    log time in the legend (about -0.5 for an unbiased estimator);
  * RMSE vs samples per pixel;
  * efficiency 1 / (MSE x time) at the final snapshot (Veach 1997, section 2.4).
"""
import base64
import csv
import html
import json
import math
import os
import shutil
import sys
from collections import defaultdict

from verdict import NO_VERDICT_FACTOR  # noqa: E402 (this script's folder is on sys.path)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_log(path):
    rows = []
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            try:
                for k in ("time_s", "preprocess_s", "rmse", "relmse", "mape", "variance"):
                    r[k] = float(r[k])
                r["spp"] = int(r["spp"])
                r["repeat"] = int(r["repeat"])
                r["nonfinite"] = int(r["nonfinite"])
                r["final"] = r["final"] == "1"
                # Time past the budget (a preprocess or pass longer than the
                # budget, issue 11); logs written before the column read 0.
                r["over_budget_s"] = float(r.get("over_budget_s") or 0)
                rows.append(r)
            except (ValueError, KeyError):
                continue  # a torn last line of an interrupted run
    return rows


def group(rows):
    """scene -> label -> repeat -> rows sorted by time."""
    out = defaultdict(lambda: defaultdict(lambda: defaultdict(list)))
    for r in rows:
        out[r["scene"]][r["label"]][r["repeat"]].append(r)
    for s in out.values():
        for l in s.values():
            for rep in l.values():
                rep.sort(key=lambda r: r["time_s"])
    return out


def slope(points):
    """Least-squares slope of log y on log x."""
    pts = [(math.log(x), math.log(y)) for x, y in points if x > 0 and y > 0]
    if len(pts) < 2:
        return float("nan")
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    if sxx == 0:
        return float("nan")
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx


def interpolate_log(xs, ys, x):
    """Log-log interpolation of a monotone-in-x curve; None outside its range."""
    if x < xs[0] or x > xs[-1]:
        return None
    for i in range(1, len(xs)):
        if x <= xs[i]:
            x0, x1, y0, y1 = xs[i - 1], xs[i], ys[i - 1], ys[i]
            if x1 == x0 or x0 <= 0 or y0 <= 0 or y1 <= 0:
                return y1
            t = (math.log(x) - math.log(x0)) / (math.log(x1) - math.log(x0))
            return math.exp(math.log(y0) + t * (math.log(y1) - math.log(y0)))
    return ys[-1]


def band(repeats, key_x, key_y):
    """Median, min and max over repeats on a common grid of x."""
    curves = [([r[key_x] for r in rows], [r[key_y] for r in rows]) for rows in repeats.values() if rows]
    lo = max(c[0][0] for c in curves)
    hi = min(c[0][-1] for c in curves)
    if not (lo > 0 and hi > lo):
        xs, ys = curves[0]
        return xs, ys, ys, ys
    grid = [lo * (hi / lo) ** (i / 39) for i in range(40)]
    grid[0], grid[-1] = lo, hi  # exact ends: rounding must not step outside any curve
    xs_out, med, mn, mx = [], [], [], []
    for x in grid:
        vals = sorted(v for v in (interpolate_log(c[0], c[1], x) for c in curves) if v is not None)
        if not vals:
            continue
        xs_out.append(x)
        med.append(vals[len(vals) // 2] if len(vals) % 2 else 0.5 * (vals[len(vals) // 2 - 1] + vals[len(vals) // 2]))
        mn.append(vals[0])
        mx.append(vals[-1])
    return xs_out, med, mn, mx


def plot_scene(scene, labels, out_dir, floor=None):
    files = {}
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for key_x, xlabel, name in (("time_s", "time (s)", "rmse_vs_time"), ("spp", "samples per pixel", "rmse_vs_spp")):
        fig, ax = plt.subplots(figsize=(7, 4.5))
        for i, (label, repeats) in enumerate(labels.items()):
            c = colors[i % len(colors)]
            xs, med, mn, mx = band(repeats, key_x, "rmse")
            pts = [(r[key_x], r["rmse"]) for rows in repeats.values() for r in rows]
            ax.plot(xs, med, color=c, label=f"{label} (slope {slope(pts):+.2f})")
            if len(repeats) > 1:
                ax.fill_between(xs, mn, mx, color=c, alpha=0.2, linewidth=0)
        if floor:
            ax.axhline(floor, color="gray", linestyle="--", linewidth=1, label=f"reference noise floor ({floor:.2g})")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(xlabel)
        ax.set_ylabel("RMSE")
        ax.set_title(f"{scene}: RMSE vs {xlabel.split(' (')[0]}")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        stem = os.path.join(out_dir, f"{name}" if scene is None else f"{scene}__{name}")
        fig.savefig(stem + ".png", dpi=110)
        fig.savefig(stem + ".svg")
        plt.close(fig)
        files[name] = stem + ".png"

    fig, ax = plt.subplots(figsize=(7, 3.5))
    effs = []
    for label, repeats in labels.items():
        finals = [rows[-1] for rows in repeats.values() if rows]
        vals = [1 / (f["rmse"] ** 2 * f["time_s"]) for f in finals if f["rmse"] > 0 and f["time_s"] > 0]
        effs.append(sum(vals) / len(vals) if vals else 0)
    ax.barh(list(labels.keys()), effs, color=colors[: len(effs)])
    ax.set_xscale("log")
    ax.set_xlabel("efficiency 1 / (MSE × time)  [higher is better]")
    ax.set_title(f"{scene}: efficiency at the final snapshot")
    fig.tight_layout()
    stem = os.path.join(out_dir, f"{scene}__efficiency")
    fig.savefig(stem + ".png", dpi=110)
    fig.savefig(stem + ".svg")
    plt.close(fig)
    files["efficiency"] = stem + ".png"
    return files


def summary(labels):
    """Per label: final metrics (mean over repeats) and time to reach the best final RMSE."""
    table = {}
    for label, repeats in labels.items():
        finals = [rows[-1] for rows in repeats.values() if rows]
        n = len(finals)
        mean = lambda k: sum(f[k] for f in finals) / n  # noqa: E731
        rm = [f["rmse"] for f in finals]
        sd = math.sqrt(sum((x - mean("rmse")) ** 2 for x in rm) / (n - 1)) if n > 1 else 0.0
        table[label] = dict(
            integrator=finals[0]["integrator"], rmse=mean("rmse"), rmse_sd=sd, relmse=mean("relmse"),
            mape=mean("mape"), variance=mean("variance"), time=mean("time_s"), spp=mean("spp"),
            preprocess=mean("preprocess_s"), nonfinite=sum(f["nonfinite"] for f in finals), repeats=n,
            over_budget=max(f["over_budget_s"] for f in finals),
            efficiency=sum(1 / (f["rmse"] ** 2 * f["time_s"]) for f in finals if f["rmse"] > 0 and f["time_s"] > 0) / n,
        )
    # "Time to reach the best final error" compares like with like: every
    # configuration's median-over-repeats curve against the lowest final
    # median, so the best configuration reaches it at its own final time.
    bands = {label: band(repeats, "time_s", "rmse") for label, repeats in labels.items()}
    best_label = min(bands, key=lambda l: bands[l][1][-1])
    target = bands[best_label][1][-1]
    best_eff = max(t["efficiency"] for t in table.values()) or 1
    for label in labels:
        xs, med, _, _ = bands[label]
        reach = next((x for x, y in zip(xs, med) if y <= target), None)
        table[label]["time_to_best"] = reach
        table[label]["relative_efficiency"] = table[label]["efficiency"] / best_eff
    return table, best_label




def data_uri(path):
    with open(path, "rb") as f:
        return "data:image/png;base64," + base64.b64encode(f.read()).decode()


def slug(s):
    return "".join(c.lower() if c.isalnum() else "-" for c in s)


def write_report(run_dir, grouped, plots, meta):
    parts = [
        "<!doctype html><html><head><meta charset='utf-8'><title>lightbench: "
        + html.escape(meta.get("experiment", "")) + "</title><style>"
        "body{font-family:sans-serif;margin:2em;max-width:1400px}table{border-collapse:collapse}"
        "td,th{border:1px solid #ccc;padding:4px 8px;text-align:right}th{background:#eee}"
        "td:first-child{text-align:left}.imgs{display:flex;flex-wrap:wrap;gap:12px}"
        ".imgs figure{margin:0}.imgs img{max-width:320px;image-rendering:pixelated}"
        "figcaption{font-size:12px;text-align:center}</style></head><body>",
        f"<h1>{html.escape(meta.get('experiment', ''))}</h1>",
        "<p>" + html.escape(
            f"lightbench {meta.get('lightbench', '')} ({meta.get('git_commit', '')}), "
            f"{meta.get('machine', {}).get('cpu', '')}, {meta.get('threads_per_run', '')} threads per run, "
            f"{meta.get('jobs', 1)} run(s) at a time; budget {meta.get('budget', {})}; "
            f"{meta.get('repeats', 1)} repeat(s), seeds {meta.get('seeds', [])}; started {meta.get('started', '')}."
        ) + "</p>",
        "<p>RMSE = sqrt(mean (x−r)²); relMSE = mean (x−r)²/(r²+ε) with ε = "
        + html.escape(str(meta.get("relmse_epsilon", ""))) + "; MAPE = 100·mean |x−r|/(|r|+ε); "
        "variance = the film's mean per-pixel variance of the mean; efficiency = 1/(MSE·time). "
        "Times include preprocessing. Error images: log10 of the per-pixel relative squared error, "
        "1e-4 (dark blue) to 10 (yellow).</p>",
    ]
    scenes_meta = {s["name"]: s for s in meta.get("scenes", [])}
    decomposition = {}
    decomposition_csv = os.path.join(run_dir, "decomposition.csv")
    if os.path.exists(decomposition_csv):
        with open(decomposition_csv, newline="") as f:
            for r in csv.DictReader(f):
                decomposition.setdefault(r["scene"], []).append(r)
    for scene, labels in grouped.items():
        table, best = summary(labels)
        parts.append(f"<h2>{html.escape(scene)}</h2>")
        ref = scenes_meta.get(scene, {}).get("reference_integrator", "")
        floor = scenes_meta.get(scene, {}).get("reference_rmse_floor")
        floor_text = (f" Its own noise (sqrt of its mean per-pixel variance) is {floor:.3g}: every measured MSE includes "
                      f"its square, so RMSE cannot be seen to fall below it." if floor else "")
        # A final RMSE within 3× the reference's own noise cannot be told
        # from the reference's error: such a comparison gets no verdict, and
        # only the others are ranked (issue 13).
        def judged(t):
            return not floor or t["rmse"] >= NO_VERDICT_FACTOR * floor
        ranked = sorted((l for l, t in table.items() if judged(t)), key=lambda l: table[l]["rmse"])
        rank = {label: i + 1 for i, label in enumerate(ranked)}
        best_text = (f"Best final RMSE: <b>{html.escape(best)}</b>." if best in rank else
                     f"Best final RMSE: {html.escape(best)}, within {NO_VERDICT_FACTOR:g}× the reference's noise floor: "
                     f"<b>no verdict (reference too noisy)</b>.")
        parts.append(f"<p>Reference: {html.escape(ref)}.{floor_text} {best_text}</p>")
        # A last pass always ends a little after the budget; only an overrun
        # above 1 % of the run's time makes the comparison unequal.
        over = {label: t["over_budget"] for label, t in table.items() if t["over_budget"] > 0.01 * t["time"]}
        if over:
            parts.append("<p><b>Over budget</b> (not an equal-time comparison for these; the table's last column): "
                         + html.escape(", ".join(f"{l} by {v:.3g} s" for l, v in sorted(over.items()))) + ".</p>")
        for name in ("rmse_vs_time", "rmse_vs_spp", "efficiency"):
            if name in plots.get(scene, {}):
                parts.append(f"<img src='{data_uri(plots[scene][name])}' style='max-width:680px'>")
        # The experiment's `metrics` list chooses the metric columns (RMSE is
        # always shown: the plots, time-to-best and efficiency are built on it).
        chosen = meta.get("metrics") or ["rmse", "relmse", "mape", "variance"]
        columns = [("relmse", "relMSE", "{:.4g}"), ("mape", "MAPE %", "{:.3g}"), ("variance", "variance", "{:.3g}")]
        columns = [c for c in columns if c[0] in chosen]
        parts.append(
            "<table><tr><th>rank</th><th>configuration</th><th>integrator</th><th>final RMSE (± sd)</th>"
            + "".join(f"<th>{c[1]}</th>" for c in columns)
            + "<th>time s</th><th>preprocess s</th><th>spp</th>"
            "<th>time to best's final RMSE</th><th>efficiency vs best</th><th>NaN/Inf</th>"
            + ("<th>over budget s</th>" if over else "") + "</tr>"
        )
        for label, t in sorted(table.items(), key=lambda kv: kv[1]["rmse"]):
            reach = f"{t['time_to_best']:.3g} s" if t["time_to_best"] is not None else "not reached"
            parts.append(
                f"<tr><td>{rank[label] if label in rank else 'no verdict (reference too noisy)'}</td>"
                f"<td>{html.escape(label)}</td><td>{html.escape(t['integrator'])}</td>"
                f"<td>{t['rmse']:.4g} ± {t['rmse_sd']:.2g}</td>"
                + "".join(f"<td>{c[2].format(t[c[0]])}</td>" for c in columns)
                + f"<td>{t['time']:.3g}</td><td>{t['preprocess']:.3g}</td>"
                f"<td>{t['spp']:.0f}</td><td>{reach}</td><td>{t['relative_efficiency']:.3g}</td>"
                f"<td>{t['nonfinite']}</td>"
                + (f"<td>{t['over_budget']:.3g}</td>" if over else "") + "</tr>"
            )
        parts.append("</table>")
        rows = decomposition.get(scene, [])
        if rows:
            # experiments/decomposition.h: MSE = bias² + variance + reference variance, in expectation.
            parts.append(
                "<p>Final MSE split over the repeats: <i>variance</i> is one run's noise (the spread of the "
                "repeats), <i>bias²</i> the squared error of their mean less its expected noise and the "
                "reference's variance; 95 % intervals (8×8-pixel tiles as batch means, conservative). "
                "An interval that excludes 0 shows a bias.</p>"
                "<table><tr><th>configuration</th><th>MSE</th><th>bias² [95 %]</th><th>variance [95 %]</th>"
                "<th>reference variance</th><th>repeats</th></tr>")
            for r in rows:
                # An unknown reference variance (a given EXR): bias² includes it, an upper bound.
                ref_var = f"{float(r['reference_variance']):.3g}" if r["reference_variance"] else "unknown (in bias²)"
                parts.append(
                    f"<tr><td>{html.escape(r['label'])}</td><td>{float(r['mse']):.3g}</td>"
                    f"<td>{float(r['bias2']):.3g} [{float(r['bias2_low']):.2g}, {float(r['bias2_high']):.2g}]</td>"
                    f"<td>{float(r['variance']):.3g} [{float(r['variance_low']):.2g}, {float(r['variance_high']):.2g}]</td>"
                    f"<td>{ref_var}</td><td>{r['repeats']}</td></tr>")
            parts.append("</table>")
        crop = scenes_meta.get(scene, {}).get("crop")
        for suffix, title in (("", "Full frame"), ("_crop", "Crop (×4)")):
            if suffix and not crop:
                continue
            parts.append(f"<h3>{title}</h3><div class='imgs'>")
            ref_png = os.path.join(run_dir, f"{scene}__reference{suffix}.png")
            if os.path.exists(ref_png):
                parts.append(f"<figure><img src='{data_uri(ref_png)}'><figcaption>reference</figcaption></figure>")
            for label in table:
                for kind, cap in (("", label), ("_error", label + " — error")):
                    png = os.path.join(run_dir, f"{scene}__{slug(label)}{kind}{suffix}.png")
                    if os.path.exists(png):
                        parts.append(f"<figure><img src='{data_uri(png)}'><figcaption>{html.escape(cap)}</figcaption></figure>")
            parts.append("</div>")
    parts.append("</body></html>")
    out = os.path.join(run_dir, "report.html")
    tmp = out + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(parts))
    os.replace(tmp, out)
    return out


def main(argv):
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    log = argv[1]
    if os.path.isdir(log):
        log = os.path.join(log, "log.csv")
    run_dir = os.path.dirname(os.path.abspath(log))
    grouped = group(read_log(log))
    if not grouped:
        print(f"report: no complete rows in {log}", file=sys.stderr)
        return 1
    meta_path = os.path.join(run_dir, "meta.json")
    meta = None
    if os.path.exists(meta_path):
        with open(meta_path) as f:
            meta = json.load(f)
    floors = {s["name"]: s.get("reference_rmse_floor") for s in (meta or {}).get("scenes", [])}
    plots = {scene: plot_scene(scene, labels, run_dir, floors.get(scene)) for scene, labels in grouped.items()}
    # The first scene's RMSE-vs-time plot also goes under a fixed name.
    first = next(iter(plots.values()))
    shutil.copyfile(first["rmse_vs_time"], os.path.join(run_dir, "rmse_vs_time.png"))
    if meta is not None:
        write_report(run_dir, grouped, plots, meta)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
