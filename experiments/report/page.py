"""report.html's sections, as strings. Every image is a data URI and the
viewer's script and styles are inlined: the file stands alone, offline.

experiments/report.py assembles them; tests/experiments/runner_test.cpp and
tests/python/test_report.py read the result (the number of <img src=' tags:
three plots, and one more per parameter sweep only when the run has sweeps;
the table's first two cells, the figcaptions, the rank groups), so change
those with the tests.
"""
import html
import json
import math
import os

from images import data_uri, png_size
from verdict_files import rank_text

HERE = os.path.dirname(os.path.abspath(__file__))
esc = html.escape


def asset(name):
    with open(os.path.join(HERE, name)) as f:
        text = f.read()
    if "</script" in text.lower() or "</style" in text.lower():
        raise ValueError(f"{name} must not contain a closing script or style tag: it is inlined")
    return text


def head(title):
    return ("<!doctype html><html lang='en'><head><meta charset='utf-8'>"
            f"<meta name='viewport' content='width=device-width'><title>lightbench: {esc(title)}</title>"
            f"<style>{asset('report.css')}\n{asset('viewer.css')}</style></head><body>")


def tail():
    return f"<script>\n{asset('viewer.js')}\n</script></body></html>"


def flow(v):
    """A meta.json value as short YAML-like flow text: {k: v, ...}."""
    if isinstance(v, dict):
        return "{" + ", ".join(f"{k}: {flow(x)}" for k, x in v.items()) + "}"
    if isinstance(v, list):
        return "[" + ", ".join(flow(x) for x in v) + "]"
    if isinstance(v, bool):
        return "true" if v else "false"
    return f"{v:g}" if isinstance(v, float) else str(v)


def describe_reference(v):
    """scenes[].reference_integrator: text, or {name, params, budget}."""
    if isinstance(v, dict) and "name" in v:
        params = v.get("params") or {}
        return " ".join(x for x in (str(v["name"]), flow(params) if params else "", str(v.get("budget") or "")) if x)
    return flow(v) if v else ""


def budget_text(b):
    if not isinstance(b, dict):
        return str(b)
    if b.get("seconds"):
        return f"{b['seconds']:g} s per run"
    return f"{b.get('spp', 0):g} spp per run"


def run_header(meta):
    m = meta
    return (
        f"<h1>{esc(m.get('experiment', ''))}</h1>"
        "<p class='meta'>" + esc(
            f"lightbench {m.get('lightbench', '')} ({m.get('git_commit', '')}), "
            f"{m.get('machine', {}).get('cpu', '')}, {m.get('threads_per_run', '')} threads per run, "
            f"{m.get('jobs', 1)} run(s) at a time; budget {budget_text(m.get('budget', {}))}; "
            f"{m.get('repeats', 1)} repeat(s), seeds {m.get('seeds', [])}; started {m.get('started', '')}"
            + (f", finished {m['finished']}." if m.get("finished") else " (not finished).")) + "</p>"
        "<p class='caption'>RMSE = sqrt(mean (x−r)²); relMSE = mean (x−r)²/(r²+ε) with ε = "
        + esc(flow(m.get("relmse_epsilon", ""))) + "; relMSE trimmed: relMSE without the pixels of largest error; "
        "MAPE = 100·mean |x−r|/(|r|+ε); variance = the film's mean per-pixel variance of the mean; efficiency = "
        "1/(error·time). Means over RGB and pixels; final values are means over the repeats, corrected for the "
        "reference's noise, with confidence intervals. Times include preprocessing.</p>")


def colour_bar():
    # log10 of 1e-4 .. 10 over the bar: one decade per fifth.
    ticks = ["10⁻⁴", "10⁻³", "10⁻²", "10⁻¹", "1", "≥10"]
    spans = "".join(f"<span style='left:{20 * i}%'>{t}</span>" for i, t in enumerate(ticks))
    return ("<div class='cbar'><div class='cbar-grad'></div>"
            f"<div class='cbar-ticks'>{spans}</div>"
            "<div class='cbar-title'>(x−r)²/(r²+ε), mean over RGB, log scale</div></div>")


def _display_width(native, target, cap):
    """An integer multiple of the native width near `target` (crisp pixels), at most `cap`."""
    return min(cap, native * max(1, round(target / native))) if native else target


def image_grid(run_dir, scene, labels, slugs, table, colour, scene_meta, verdict=None):
    """One row per configuration (the reference first): final image, error
    image, crop, crop's error; fixed column widths. None without images."""
    ref_png = os.path.join(run_dir, f"{scene}__reference.png")
    stems = {l: os.path.join(run_dir, f"{scene}__{slugs[l]}") for l in labels}
    if not os.path.exists(ref_png) and not any(os.path.exists(s + ".png") for s in stems.values()):
        return None
    size = png_size(ref_png) if os.path.exists(ref_png) else None
    w, h = size or (256, 256)
    full = _display_width(w, 256, 384)
    crop = scene_meta.get("crop")
    crop_w = _display_width(crop[2] - crop[0], 200, 256) if crop else 0
    cols = [170, full, full] + ([crop_w, crop_w] if crop else [])
    out = [f"<div class='grid' style='grid-template-columns:{' '.join(f'{c}px' for c in cols)}'>",
           "<div class='hd'></div><div class='hd'>final image</div>",
           "<div class='hd'>error against the reference</div>"]
    if crop:
        out.append(f"<div class='hd'>crop, ×{crop_w // (crop[2] - crop[0])}</div>"
                   "<div class='hd'>error, crop (same scale)</div>")

    def cell(path, caption, overlay=""):
        if not os.path.exists(path):
            return f"<figure><figcaption>{esc(caption)}: no image</figcaption></figure>"
        return (f"<figure><div class='frame'><img src='{data_uri(path)}' alt='{esc(caption)}'>{overlay}</div>"
                f"<figcaption>{esc(caption)}</figcaption></figure>")

    rect = ""
    if crop and w and h:
        x0, y0, x1, y1 = crop  # pixels, [x0, x1) × [y0, y1), y down (experiments/metrics.cpp cropImage)
        rect = (f"<div class='croprect' style='left:{100 * x0 / w:.4f}%;top:{100 * y0 / h:.4f}%;"
                f"width:{100 * (x1 - x0) / w:.4f}%;height:{100 * (y1 - y0) / h:.4f}%'></div>")
    floor = scene_meta.get("reference_rmse_floor")
    out.append("<div class='rowlabel'><b>reference</b><br><span class='sub'>"
               + esc(describe_reference(scene_meta.get("reference_integrator"))) + "</span>"
               + (f"<br><span class='num'>noise floor (RMSE) {floor:.3g}</span>" if floor else "") + "</div>")
    # The reference has no error image: its cell holds the error images' colour bar.
    out.append(cell(ref_png, "reference", rect)
               + f"<div class='refnote'>{colour_bar()}<p>The error images: per-pixel relative squared error "
               "against the reference (its image mean is that run's relMSE); NaN/Inf in yellow. The crop's use "
               "the same scale.</p></div>")
    if crop:
        out.append(cell(os.path.join(run_dir, f"{scene}__reference_crop.png"), "reference — crop") + "<div></div>")
    for label in labels:
        t, s = table[label], stems[label]
        kind = "unbiased" if t["unbiased"] else "biased/consistent"
        out.append(
            f"<div class='rowlabel'><span class='swatch{'' if t['unbiased'] else ' dashed'}' "
            f"style='background-color:{colour[label]}'></span><b>{esc(label)}</b><br>"
            f"<span class='sub'>{esc(t['integrator'])}, {kind}</span><br>"
            + (f"<span class='num'>rank {esc(rank_text(verdict.row(label)))}: {esc(metric_name(verdict.metric))} "
               f"{_num(verdict.row(label)['value'])}</span><br>" if verdict and verdict.row(label) else
               f"<span class='num'>RMSE {t['rmse']:.3g} (raw)<br>relMSE {t['relmse']:.3g}</span><br>") +
            f"<span class='sub'>{t['spp']:.0f} spp, {t['time']:.3g} s</span></div>")
        out.append(cell(s + ".png", label) + cell(s + "_error.png", label + " — error"))
        if crop:
            out.append(cell(s + "_crop.png", label + " — crop")
                       + cell(s + "_error_crop.png", label + " — error, crop"))
    out.append("</div>")
    caption = ("Final images of the first repeat, sRGB, clipped at 1. Error: per-pixel relative squared error "
               "against the reference, the runner's false colour (viridis, log scale, 10⁻⁴ to 10; NaN/Inf and "
               "anything above 10 in yellow); its mean over the image is that run's relMSE.")
    if crop:
        caption += (f" Crop: pixels [{crop[0]}, {crop[2]}) × [{crop[1]}, {crop[3]}), outlined in red on the "
                    "reference; its metrics are the table's crop columns.")
    out.append(f"<p class='caption'>{caption}</p>")
    return "".join(out)


def viewer_block(index, payload, notes):
    ident = f"lbv-data-{index}"
    data = json.dumps(payload, separators=(",", ":")).replace("</", "<\\/")
    ds = payload["downsample"]
    text = ("Keys (with the pointer over the viewer, or after a click in it): 1–9 and 0 choose an image (as "
            "numbered), ← → step through them; a click on the image flips back to the one shown before; the "
            "wheel zooms, a drag pans, a double-click or f fits; "
            + ("c zooms to the crop (outlined in red); " if payload["crop"] else "")
            + "e shows the relative squared error (the grid's colour scale); + and − change the exposure by half a "
            "stop. The exposure multiplies the linear data by 2<sup>stops</sup> before sRGB encoding. Images: "
            + ("the run's EXRs" if payload["source"] == "exr" else "the run's PNGs decoded to linear")
            + f", embedded as half floats (about three significant digits), {payload['width']}×{payload['height']} "
            "pixels" + (f" (box-filtered by {ds}×)" if ds > 1 else "") + ".")
    parts = [f"<script type='application/json' id='{ident}'>{data}</script>",
             f"<div class='lbv-wrap'><div class='lb-viewer' data-source='{ident}'></div><div class='lbv-side'>",
             "<noscript><p class='warn'>The viewer needs JavaScript.</p></noscript>",
             f"<p class='caption'>{text}</p>"]  # no user text in it: numbers only
    parts += [f"<p class='warn'>Viewer: {n}.</p>" for n in notes]
    return "".join(parts) + "</div></div>"


def plot_figure(path, caption):
    return f"<figure class='plot'><img src='{data_uri(path)}' alt=''><figcaption>{caption}</figcaption></figure>"


def _num(v):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "—"
    if math.isinf(v):
        return "∞"
    return f"{v:.3g}"


def _interval(lo, hi):
    return f"<span class='ci'>[{_num(lo)}, {_num(hi)}]</span>"


def ranking_table(table, verdict, chosen, crop, meta=None):
    """The final-snapshot table in the verdict's order (best first). Rows
    begin with the rank group and the label, in plain cells. Without verdict
    files: sorted by the raw final RMSE, no ranks."""
    metric = verdict.metric if verdict else "rmse"
    others = [m for m in ("rmse", "relmse", "relmse_trimmed") if m != metric and m in chosen]
    crop_metrics = [m for m in ("rmse_crop", "relmse_crop") if crop and m != metric]
    raw_cols = [c for c in (("mape", "MAPE %"), ("variance", "variance")) if c[0] in chosen]
    over = any(t["over_budget"] > 0.01 * t["time"] for t in table.values())
    baseline = verdict.rows[0]["baseline"] if verdict and verdict.rows else None
    head = (f"<th>rank</th><th>configuration</th><th>integrator</th><th>{esc(metric_name(metric))} "
            "[interval]</th><th>vs next: Holm p</th>"
            + "".join(f"<th>{esc(metric_name(m))}</th>" for m in others + crop_metrics)
            + "".join(f"<th>{c[1]} (raw)</th>" for c in raw_cols)
            + "<th>time s (pre&shy;process)</th><th>spp</th><th>slope vs time: RMSE, relMSE</th>"
            + (f"<th>time to {esc(baseline)}'s error, s</th><th>efficiency</th><th>speed-up over {esc(baseline)}</th>"
               if verdict else "<th>efficiency 1/(MSE·t)</th>")
            + "<th>NaN/ Inf</th>" + ("<th>over budget s</th>" if over else ""))
    out = [f"<div class='scroll'><table class='stats ranking'><tr>{head}</tr>"]
    order = [r["label"] for r in verdict.rows if r["label"] in table] if verdict else sorted(
        table, key=lambda l: table[l]["rmse"])
    no_slope = {"biased/consistent": "b"}
    for label in order:
        t = table[label]
        slopes = (f"—<sup>{no_slope.get(t['no_slope'], 'p')}</sup>" if t["no_slope"] else
                  f"{t['slope_rmse']:+.2f}, {t['slope_relmse']:+.2f}")
        if verdict:
            r = verdict.row(label)
            pair = verdict.next_pair(label)
            nxt = (f"{_num(pair['p_holm'])}{'' if pair['decided'] else ' (tied)'}" if pair else "")
            cells = (f"<td>{esc(rank_text(r))}</td><td>{esc(label)}</td>"
                     f"<td>{esc(t['integrator']).replace('_', '_&#8203;')}</td>"
                     f"<td>{_num(r['value'])} {_interval(r['ci_low'], r['ci_high'])}</td><td>{nxt}</td>")
            for m in others + crop_metrics:
                e = verdict.metrics.get((label, m))
                cells += f"<td>{_num(e['value'])} {_interval(e['ci_low'], e['ci_high'])}</td>" if e else "<td>–</td>"
        else:
            cells = (f"<td>–</td><td>{esc(label)}</td><td>{esc(t['integrator']).replace('_', '_&#8203;')}</td>"
                     f"<td>{_num(t['rmse'])} (raw)</td><td></td>")
            for m in others + crop_metrics:
                v = t.get(m)
                cells += f"<td>{_num(v)} (raw)</td>" if v is not None else "<td>–</td>"
        cells += "".join(f"<td>{_num(t[c[0]])}</td>" for c in raw_cols)
        cells += f"<td>{t['time']:.3g} ({t['preprocess']:.2g})</td><td>{t['spp']:.0f}</td><td>{slopes}</td>"
        if verdict:
            reach = r["time_to_target_s"]
            reach_text = "—" if math.isnan(reach) else _num(reach)
            if not math.isnan(reach) and not (math.isnan(r["time_to_target_low_s"]) and math.isnan(
                    r["time_to_target_high_s"])):
                high = r["time_to_target_high_s"]
                reach_text += " " + _interval(r["time_to_target_low_s"], high) if not math.isnan(high) else (
                    f" <span class='ci'>[{_num(r['time_to_target_low_s'])}, beyond]</span>")
            cells += (f"<td>{reach_text}</td><td>{_num(r['efficiency'])} "
                      f"{_interval(r['efficiency_low'], r['efficiency_high'])}</td>"
                      f"<td>{_num(r['speedup'])} {_interval(r['speedup_low'], r['speedup_high'])}</td>")
        else:
            cells += f"<td>{_num(t['efficiency'])}</td>"
        cells += f"<td>{t['nonfinite']}</td>" + (f"<td>{t['over_budget']:.3g}</td>" if over else "")
        out.append(f"<tr>{cells}</tr>")
    out.append("</table></div>")
    return "".join(out)


def metric_name(m):
    return {"rmse": "RMSE", "relmse": "relMSE", "relmse_trimmed": "relMSE trimmed", "rmse_crop": "crop RMSE",
            "relmse_crop": "crop relMSE"}.get(m, m)


def ranking_caption(verdict, meta):
    if not verdict:
        return "<p class='caption'>Raw final RMSE, mean over the repeats; no ranks without verdict files.</p>"
    v = (meta or {}).get("verdict") or {}
    confidence, looks = v.get("confidence", 0.95), v.get("looks", 1)
    trim = v.get("trim_fraction", 0.001)
    return (
        f"<p class='caption'>Best first by <b>{esc(metric_name(verdict.metric))}</b>, corrected for the reference's "
        "noise (each squared term less the reference's variance of the mean there: an unbiased estimate of the "
        "error against the true image). Its interval: "
        f"{100 * confidence:g} %" + (f" at the level split among {looks} looks" if looks > 1 else "")
        + ", Student t over the repeats with the reference's own part (one repeat: 8×8-pixel tiles as batch "
        "means), docs/testing.md. <b>Rank</b>: the ranks the pairwise tests allow (Welch's t on the repeats' "
        "values with the reference's part of the difference; Holm's correction over every pair of the scene), "
        "e.g. 2–3 when two configurations cannot be told apart. <b>vs next</b>: Holm's p-value of the "
        "difference to the next row. Other metrics: corrected, with intervals; MAPE and the film's variance "
        f"raw. relMSE trimmed rejects the {100 * trim:g} % of pixels with the largest error. Slope: of log "
        "error on log time (see the plots); none for biased or consistent methods (b) or where preprocessing "
        "takes over half the time (p). Time to the baseline's error: when the mean curve reaches the "
        "baseline's final value (interval: when the band's edges do; —: not within the budget). Efficiency: "
        "1/(error·time) with the error's interval; speed-up: efficiency over the baseline's, its interval "
        "from both errors' intervals (conservative; ∞: the error may be 0).</p>")


def decomposition_table(rows):
    # experiments/decomposition.h: MSE = bias² + variance + reference variance, in expectation.
    out = ["<p class='caption'>Final MSE split over the repeats: <i>variance</i> is one run's noise (the spread of "
           "the repeats), <i>bias²</i> the squared error of their mean less its expected noise and the reference's "
           "variance; 95 % intervals (8×8-pixel tiles as batch means, conservative). An interval that excludes 0 "
           "shows a bias.</p>"
           "<table class='stats'><tr><th>configuration</th><th>MSE</th><th>bias² [95 %]</th><th>variance [95 %]</th>"
           "<th>reference variance</th><th>repeats</th></tr>"]
    for r in rows:
        # An unknown reference variance (a given EXR): bias² includes it, an upper bound.
        ref_var = f"{float(r['reference_variance']):.3g}" if r["reference_variance"] else "unknown (in bias²)"
        out.append(
            f"<tr><td>{esc(r['label'])}</td><td>{float(r['mse']):.3g}</td>"
            f"<td>{float(r['bias2']):.3g} [{float(r['bias2_low']):.2g}, {float(r['bias2_high']):.2g}]</td>"
            f"<td>{float(r['variance']):.3g} [{float(r['variance_low']):.2g}, {float(r['variance_high']):.2g}]</td>"
            f"<td>{ref_var}</td><td>{r['repeats']}</td></tr>")
    out.append("</table>")
    return "".join(out)
