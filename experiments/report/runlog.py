"""A run's log.csv read into curves and final-snapshot statistics.

Everything the report states about errors is computed here, from the log
alone: the images are only shown, never measured again.
"""
import csv
import math
import re
from collections import defaultdict

# Integrators whose estimate is biased (consistent at best): a straight
# line through their log error has no -0.5 (or -1) to be compared with, so
# no slope is fitted. Used when meta.json does not say per configuration.
BIASED_INTEGRATORS = ("photon", "sppm", "irradiance_cache")

# Crop metrics: absent (empty cells) when the scene has no crop.
CROP_KEYS = ("rmse_crop", "relmse_crop", "mape_crop")
# Columns of later logs (issue 32): the trimmed relMSE and the squared errors
# corrected for the reference's noise; None in a log written before them.
OPTIONAL_KEYS = ("relmse_trimmed", "mse_corrected", "relmse_corrected", "relmse_trimmed_corrected",
                 "mse_crop_corrected", "relmse_crop_corrected")
# A metric's curve as the plots and slopes read it: the corrected column
# (for an RMSE, its square root) where the log has it, else the raw one.
CORRECTED = {"rmse": ("mse_corrected", True), "relmse": ("relmse_corrected", False),
             "rmse_crop": ("mse_crop_corrected", True), "relmse_crop": ("relmse_crop_corrected", False)}


def corrected_value(row, key):
    """The row's `key` metric corrected for the reference's noise (None where
    it is not positive: a log scale cannot show it), or the raw value for a
    log without the corrected columns."""
    column, root = CORRECTED.get(key, (None, False))
    if column is None or row.get(column) is None:
        return row.get(key)
    v = row[column]
    if not v > 0:
        return None
    return math.sqrt(v) if root else v


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
                for k in CROP_KEYS + OPTIONAL_KEYS:
                    r[k] = float(r[k]) if r.get(k) else None
                rows.append(r)
            except (ValueError, KeyError, TypeError):
                continue  # a torn last line of an interrupted run
    return rows


def group(rows):
    """scene -> label -> repeat -> rows sorted by time (insertion ordered)."""
    out = defaultdict(lambda: defaultdict(lambda: defaultdict(list)))
    for r in rows:
        out[r["scene"]][r["label"]][r["repeat"]].append(r)
    for s in out.values():
        for l in s.values():
            for rep in l.values():
                rep.sort(key=lambda r: r["time_s"])
    return out


def slug(s):
    """experiments/experiment.cpp slug(): the image files' names. Byte by
    byte over UTF-8, ASCII letters and digits kept, as the C++ does (a
    non-ASCII letter is one '-' per byte there)."""
    return "".join(chr(b).lower() if chr(b).isascii() and chr(b).isalnum() else "-" for b in s.encode("utf-8"))


def sweep_members(labels, meta):
    """The parameter sweeps among `labels`: {group: [(label, values), ...]},
    groups and members in the order of `labels`. meta.json marks each member
    of a sweep with "sweep": {"group", "values"}; configurations without that
    key (and every one when there is no meta.json) belong to none. `values`
    is ordered as the label names the keys ("SPPM radius=0.01, alpha=0.5"):
    meta.json's JSON objects come with their keys sorted, the label keeps the
    experiment file's order."""
    marks = {c.get("label"): c["sweep"] for c in (meta or {}).get("configurations", [])
             if isinstance(c.get("sweep"), dict) and c["sweep"].get("group")}
    out = {}
    for label in labels:
        mark = marks.get(label)
        if mark is None:
            continue
        values = mark.get("values") or {}
        if not values:
            continue  # nothing swept to plot against: an ordinary configuration
        where = {k: re.search(rf"(?:^|[\s,]){re.escape(str(k))}=", label) for k in values}
        keys = sorted(values, key=lambda k: (where[k] is None, where[k].start() if where[k] else 0))
        out.setdefault(mark["group"], []).append((label, {k: values[k] for k in keys}))
    return out


def member_name(label, group):
    """A member's label without its group's name: what the legend lists under the group."""
    return label[len(group):].strip() if label.startswith(group + " ") else label


def has_crop(labels):
    return any(r["rmse_crop"] is not None for reps in labels.values() for rows in reps.values() for r in rows)


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
    """Median, min and max over repeats on a common grid of x (the range all
    repeats cover): the plots' fallback for a run without verdict files,
    which hold the mean curves with their confidence intervals."""
    curves = [([r[key_x] for r in rows], [r[key_y] for r in rows])
              for rows in repeats.values() if rows and all(r[key_y] is not None for r in rows)]
    if not curves:
        return [], [], [], []
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


def unbiased(label, integrator, meta):
    """Whether a configuration's estimator is unbiased: meta.json's word when
    it has one (an `unbiased` key per configuration), else by integrator,
    VCM being unbiased only in its BDPT mode (integrators/registry.cpp)."""
    for c in (meta or {}).get("configurations", []):
        if c.get("label") == label:
            if isinstance(c.get("unbiased"), bool):
                return c["unbiased"]
            if c.get("integrator"):
                integrator = c["integrator"]
            if integrator == "vcm":
                # resolved_parameters: a mapping, or (older meta.json) its YAML flow text.
                p = c.get("resolved_parameters") or {}
                if isinstance(p, dict):
                    return p.get("mode") == "bpt"
                m = re.search(r"\bmode:\s*([A-Za-z_]+)", str(p))
                return bool(m) and m.group(1) == "bpt"
    if integrator == "vcm":
        return False  # without meta.json the mode is unknown: VCM's default mode merges
    return integrator not in BIASED_INTEGRATORS


def no_slope_reason(t):
    """Why a configuration gets no fitted slope, or None when it gets one."""
    if not t["unbiased"]:
        return "biased/consistent"
    if t["time"] > 0 and t["preprocess"] > 0.5 * t["time"]:
        return f"preprocess {100 * t['preprocess'] / t['time']:.0f} % of time"
    return None


def mean_sd(values):
    n = len(values)
    m = sum(values) / n
    return m, (math.sqrt(sum((x - m) ** 2 for x in values) / (n - 1)) if n > 1 else 0.0)


def summary(labels, meta=None):
    """Per label: final raw metrics (mean over repeats), times, samples and
    slopes. The verdict (rank groups, intervals, corrected values,
    efficiency) is the run's verdict files' (experiments/report/verdict_files.py)."""
    table = {}
    for label, repeats in labels.items():
        finals = [rows[-1] for rows in repeats.values() if rows]
        n = len(finals)
        mean = lambda k: sum(f[k] for f in finals) / n  # noqa: E731
        rmse, rmse_sd = mean_sd([f["rmse"] for f in finals])
        relmse, relmse_sd = mean_sd([f["relmse"] for f in finals])
        t = dict(
            integrator=finals[0]["integrator"], rmse=rmse, rmse_sd=rmse_sd, relmse=relmse, relmse_sd=relmse_sd,
            mape=mean("mape"), variance=mean("variance"), time=mean("time_s"), spp=mean("spp"),
            preprocess=mean("preprocess_s"), nonfinite=sum(f["nonfinite"] for f in finals), repeats=n,
            over_budget=max(f["over_budget_s"] for f in finals),
            efficiency=sum(1 / (f["rmse"] ** 2 * f["time_s"]) for f in finals if f["rmse"] > 0 and f["time_s"] > 0) / n,
        )
        for k in CROP_KEYS:
            vals = [f[k] for f in finals if f[k] is not None]
            t[k] = sum(vals) / len(vals) if vals else None
        t["unbiased"] = unbiased(label, t["integrator"], meta)
        t["no_slope"] = no_slope_reason(t)
        for key in ("rmse", "relmse", "rmse_crop", "relmse_crop"):
            # Corrected for the reference's noise: near its floor the raw
            # error flattens, the corrected one keeps the estimator's slope.
            pts = [(r["time_s"], corrected_value(r, key)) for rows in repeats.values() for r in rows]
            pts = [(x, y) for x, y in pts if y is not None]
            t["slope_" + key] = None if t["no_slope"] else slope(pts)
        table[label] = t
    return table
