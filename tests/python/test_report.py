"""experiments/report.py on a small synthetic run: the HTML's structure, its
plots and sweeps (the viewer's data and its run in headless Chromium:
test_report_viewer.py).

    /usr/bin/python3 -m pytest tests/python

The run folder has a space in its path, as a user's might.
"""
import base64
import csv
import json
import math
import os
import re
import subprocess
import sys

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.colors  # noqa: E402
import matplotlib.container  # noqa: E402
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
REPORT = os.path.join(REPO, "experiments", "report.py")
sys.path.insert(0, os.path.join(REPO, "experiments", "report"))
import images  # noqa: E402
import plots  # noqa: E402
import runlog  # noqa: E402

CHROMIUM = "/usr/bin/chromium"
SCENE = "box"
W, H = 24, 16
CROP = [4, 4, 12, 10]
# Two configurations, one unbiased and one biased, so one slope is fitted and one is not.
CONFIGS = [("alpha (path)", "path"), ("beta: photons", "photon")]
FLOOR = 0.01  # the reference's noise floor


def slug(s):
    return "".join(c.lower() if c.isalnum() else "-" for c in s)


def write_run(run_dir, with_meta=True, floor=FLOOR, structured=False, configs=CONFIGS, sweeps=None, with_verdict=True,
              tied=False):
    """structured: meta.json as the nlohmann-json writer has it (mappings
    where the older writer wrote YAML flow text). sweeps: {label: (group,
    values)} for the configurations that are members of a sweep.
    with_verdict: the verdict files too (write_verdict; tied as it takes)."""
    os.makedirs(run_dir)
    rng = np.random.default_rng(1)
    with open(os.path.join(run_dir, "log.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow("scene,label,integrator,repeat,seed,time_s,preprocess_s,spp,rmse,relmse,mape,variance,nonfinite,"
                   "rmse_crop,relmse_crop,mape_crop,over_budget_s,final".split(","))
        for n, (label, integrator) in enumerate(configs):
            for repeat in range(2):
                for i, t in enumerate([0.25, 0.5, 1.0, 2.0]):
                    # alpha falls as t^-0.5 (unbiased); beta flattens at 0.015, within 3x the floor.
                    rmse = (0.1 * t ** -0.5 if integrator == "path" else 0.015 + 0.02 * t ** -1) * (1 + 0.05 * repeat)
                    rmse *= 1 + 0.1 * n * (label in (sweeps or {}))  # a sweep's members differ
                    w.writerow([SCENE, label, integrator, repeat, 1 + 7919 * repeat, t, 0.01, 8 * 2 ** i, rmse,
                                rmse ** 2 * 3, 10 * rmse, rmse ** 2, 0, 2 * rmse, 6 * rmse ** 2, 20 * rmse, 0,
                                int(i == 3)])
    # The images: dim, so that the viewer's exposure has room to brighten them.
    ref = 0.05 + 0.25 * rng.random((H, W, 3))
    images = {"reference": ref}
    for label, _ in configs:
        images[slug(label)] = np.clip(ref + 0.1 * rng.standard_normal((H, W, 3)), 0, 1)
    x0, y0, x1, y1 = CROP
    for name, img in images.items():
        stem = os.path.join(run_dir, f"{SCENE}__{name}")
        mpimg.imsave(stem + ".png", img)
        mpimg.imsave(stem + "_crop.png", np.kron(img[y0:y1, x0:x1], np.ones((4, 4, 1))))
        if name != "reference":
            err = rng.random((H, W, 3))
            mpimg.imsave(stem + "_error.png", err)
            mpimg.imsave(stem + "_error_crop.png", np.kron(err[y0:y1, x0:x1], np.ones((4, 4, 1))))
    if not with_meta:
        return
    meta = {
        "experiment": "synthetic", "lightbench": "test", "git_commit": "0000000", "started": "now",
        "finished": "later", "machine": {"cpu": "test"}, "threads_per_run": 1, "jobs": 1,
        "budget": {"seconds": 2, "spp": 0}, "repeats": 2, "seeds": [1, 7920],
        "metrics": ["rmse", "relmse", "mape", "variance"], "relmse_epsilon": 0.01,
        "verdict": {"rank_by": "relmse", "confidence": 0.95, "baseline": configs[0][0], "looks": 1,
                    "trim_fraction": 0.001},
        "scenes": [{"name": SCENE, "reference": "", "reference_integrator": "path {} 64 spp",
                    "reference_used": "", "reference_rmse_floor": floor, "crop": CROP}],
        "configurations": [{"label": l, "integrator": i, "resolved_parameters": "{}"} for l, i in configs],
    }
    for c in meta["configurations"]:
        if c["label"] in (sweeps or {}):
            group, values = sweeps[c["label"]]
            c["sweep"] = {"group": group, "values": values}
    if structured:
        meta["scenes"][0]["reference_integrator"] = {"name": "path", "params": {"mis": "power"}, "budget": "64 spp"}
        meta["scenes"][0]["reference_exr"] = f"{SCENE}__reference.exr"  # not written: the viewer falls back
        for c in meta["configurations"]:
            c["resolved_parameters"] = {"max_depth": 32}
            c["unbiased"] = c["integrator"] == "path"
    with open(os.path.join(run_dir, "meta.json"), "w") as f:
        json.dump(meta, f)
    if with_verdict:
        write_verdict(run_dir, configs, tied)
    with open(os.path.join(run_dir, "decomposition.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow("scene,label,integrator,repeats,mse,bias2,bias2_low,bias2_high,variance,variance_low,"
                   "variance_high,reference_variance".split(","))
        for label, integrator in configs:
            w.writerow([SCENE, label, integrator, 2, 1e-3, 1e-4, 0, 2e-4, 9e-4, 8e-4, 1e-3, 1e-5])


VERDICT_HEADER = ("scene,label,metric,value,ci_low,ci_high,rank_group,decided,repeats,raw_value,time_s,efficiency,"
                  "efficiency_low,efficiency_high,speedup,speedup_low,speedup_high,time_to_target_s,"
                  "time_to_target_low_s,time_to_target_high_s,baseline")
PAIRS_HEADER = ("scene,metric,better,worse,difference,difference_low,difference_high,p,p_holm,decided,adjacent,"
                "reference_share,repeats_better,repeats_worse,reason")
REASON = "the runs' spread (2 and 2 repeats; repeats: {until_decided: true} adds repeats until decided)"


def write_verdict(run_dir, configs=CONFIGS, tied=False):
    """Verdict files as experiments/verdict/run_folder.cpp writes them: the
    configurations ranked in order, each 20 % worse than the one before;
    tied: the first two in one rank group, their pair undecided."""
    labels = [l for l, _ in configs]
    n = len(labels)
    with open(os.path.join(run_dir, "verdict.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(VERDICT_HEADER.split(","))
        for i, label in enumerate(labels):
            group = "1-2" if tied and i < 2 else str(i + 1)
            v = 0.01 * 1.2 ** i
            w.writerow([SCENE, label, "relmse", v, 0.9 * v, 1.1 * v, group, "false" if tied and i < 2 else "true", 2,
                        1.05 * v, 2.0, 1 / (2 * v), 1 / (2.2 * v), 1 / (1.8 * v), 0.01 / v, 0.8 * 0.01 / v,
                        1.2 * 0.01 / v, 2.0 * v / 0.01, 1.5 * v / 0.01, "", labels[0]])
    with open(os.path.join(run_dir, "verdict_pairs.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(PAIRS_HEADER.split(","))
        for i in range(n):
            for j in range(i + 1, n):
                undecided = tied and i == 0 and j == 1
                w.writerow([SCENE, "relmse", labels[i], labels[j], -0.002, -0.003, -0.001, 0.3 if undecided else 1e-4,
                            0.3 if undecided else 1e-3, "false" if undecided else "true",
                            "true" if j == i + 1 else "false", 0.1, 2, 2, REASON if undecided else ""])
    with open(os.path.join(run_dir, "verdict_metrics.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow("scene,label,metric,value,ci_low,ci_high,raw_value,repeats".split(","))
        for i, label in enumerate(labels):
            for m in ("rmse", "relmse", "relmse_trimmed", "rmse_crop", "relmse_crop"):
                v = 0.1 * 1.1 ** i
                w.writerow([SCENE, label, m, v, 0.9 * v, 1.1 * v, v, 2])
    with open(os.path.join(run_dir, "verdict_curves.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow("scene,label,metric,x,x_value,mean,low,high".split(","))
        for i, label in enumerate(labels):
            for m in ("rmse", "relmse", "rmse_crop", "relmse_crop"):
                for x, xs in (("time_s", [0.25, 0.5, 1, 2]), ("spp", [8, 16, 32, 64])):
                    for k, at in enumerate(xs):
                        v = 0.1 * 1.1 ** i / 2 ** (k / 2)
                        # The first point's band reaches below zero: drawn to the axis' bottom.
                        w.writerow([SCENE, label, m, x, at, v, -v if k == 0 else 0.8 * v, 1.2 * v])


def run_report(arg):
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    p = subprocess.run(["/usr/bin/python3", REPORT, arg], capture_output=True, text=True, timeout=60, env=env)
    assert p.returncode == 0, p.stderr
    return p


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    run_dir = str(tmp_path_factory.mktemp("report") / "results with space" / "run 1")
    write_run(run_dir)
    run_report(run_dir)
    path = os.path.join(run_dir, "report.html")
    with open(path, encoding="utf-8") as f:
        return path, f.read()


def test_report_has_one_row_per_configuration(report):
    _, text = report
    rows = re.findall(r"<div class='rowlabel'>.*?<b>(.*?)</b>", text)
    assert rows == ["reference"] + [l for l, _ in CONFIGS]
    for label, _ in CONFIGS:  # image, error image, crop and the crop's error, captioned
        for kind in ("", " — error", " — crop", " — error, crop"):
            assert f"<figcaption>{label}{kind}</figcaption>" in text
        assert re.search(rf"<tr><td>[^<]*</td><td>{re.escape(label)}</td>", text), label
    assert "Final MSE split over the repeats" in text
    assert "class='croprect'" in text and "class='cbar'" in text


def test_report_is_self_contained(report):
    _, text = report
    with open(os.path.join(REPO, "experiments", "report", "viewer.js")) as f:
        assert f.read().strip() in text, "viewer.js is inlined"
    assert not re.search(r"<script[^>]*\bsrc=", text)
    assert not re.search(r"""(?:src|href)\s*=\s*["']?\s*(?:https?:)?//""", text), "no external resources"
    assert "http://" not in text and "https://" not in text
    for src in re.findall(r"<img src='([^']*)'", text):
        assert src.startswith("data:image/png;base64,")


def test_viewer_data_decode_to_the_images(report):
    path, text = report
    data = json.loads(re.search(r"<script type='application/json' id='lbv-data-0'>(.*?)</script>", text).group(1))
    assert (data["width"], data["height"], data["downsample"], data["crop"]) == (W, H, 1, CROP)
    assert [im["name"] for im in data["images"]] == ["reference"] + [l for l, _ in CONFIGS]
    ref = np.frombuffer(base64.b64decode(data["images"][0]["data"]), dtype="<f2").reshape(H, W, 3)
    png = mpimg.imread(os.path.join(os.path.dirname(path), f"{SCENE}__reference.png"))[..., :3]
    linear = np.where(png <= 0.04045, png / 12.92, ((png + 0.055) / 1.055) ** 2.4)
    assert np.allclose(ref, linear, rtol=2e-3, atol=1e-4)
    assert data["source"] == "png" or "lightbench" not in text  # no EXRs in this run
    assert "exposure is limited to the display range" in text


def test_rank_groups_intervals_and_the_ranked_metric(report):
    _, text = report
    alpha, beta = CONFIGS[0][0], CONFIGS[1][0]
    assert "Ranked by <b>relMSE</b>, corrected" in text and "Best: <b>" + alpha + "</b>, rank 1 decided." in text
    row = re.search(rf"<tr><td>1</td><td>{re.escape(alpha)}</td>.*?</tr>", text).group(0)
    assert "0.01 <span class='ci'>[0.009, 0.011]</span>" in row  # value [interval], verdict.csv's
    assert "-0.50" in row  # 0.1 t^-0.5 (the raw log: it has no corrected columns)
    row = re.search(rf"<tr><td>2</td><td>{re.escape(beta)}</td>.*?</tr>", text).group(0)
    assert "—<sup>b</sup>" in row
    assert "no verdict" not in text and "Undecided neighbours" not in text
    assert "95 % confidence interval (Student t over the repeats" in text
    assert f"speed-up over {alpha}" in text


def test_tied_neighbours_are_listed_with_why(tmp_path):
    run_dir = str(tmp_path / "tied")
    write_run(run_dir, tied=True)
    run_report(run_dir)
    with open(os.path.join(run_dir, "report.html"), encoding="utf-8") as f:
        text = f.read()
    alpha, beta = CONFIGS[0][0], CONFIGS[1][0]
    assert f"<tr><td>1–2 (tied)</td><td>{alpha}</td>" in text and f"<tr><td>1–2 (tied)</td><td>{beta}</td>" in text
    assert "in rank group 1–2 (tied) with " + beta in text
    assert "<b>Undecided neighbours</b>" in text and html_escape(REASON) in text


def html_escape(s):
    import html
    return html.escape(s)


def test_without_verdict_files_nothing_is_ranked(tmp_path):
    run_dir = str(tmp_path / "no verdict")
    write_run(run_dir, with_verdict=False)
    run_report(run_dir)
    with open(os.path.join(run_dir, "report.html"), encoding="utf-8") as f:
        text = f.read()
    assert "No verdict files in this run folder" in text
    assert re.search(r"<tr><td>–</td><td>[^<]*</td>", text)
    assert "<tr><td>1</td>" not in text


def test_no_floor_and_structured_meta(tmp_path):
    run_dir = str(tmp_path / "no floor")
    write_run(run_dir, floor=None, structured=True)
    run_report(run_dir)
    with open(os.path.join(run_dir, "report.html"), encoding="utf-8") as f:
        text = f.read()
    assert "Its variance is unknown" in text
    assert "<tr><td>1</td>" in text and "<tr><td>2</td>" in text
    assert "path {mis: power} 64 spp" in text
    assert "—<sup>b</sup>" in text


def test_log_only_gives_plots(tmp_path):
    run_dir = str(tmp_path / "log only")
    write_run(run_dir, with_meta=False)
    run_report(os.path.join(run_dir, "log.csv"))
    for name in ("rmse_vs_time.png", f"{SCENE}__rmse_vs_time.svg", f"{SCENE}__relmse_vs_time.png",
                 f"{SCENE}__rmse_vs_spp.png", f"{SCENE}__convergence.png", f"{SCENE}__crop_convergence.png",
                 f"{SCENE}__efficiency.png"):
        assert os.path.exists(os.path.join(run_dir, name)), name
    assert not os.path.exists(os.path.join(run_dir, "report.html"))


def test_slope_rules():
    t = dict(unbiased=True, time=10.0, preprocess=6.0)
    assert runlog.no_slope_reason(t).startswith("preprocess 60 %")
    assert runlog.no_slope_reason(dict(t, preprocess=1.0)) is None
    assert runlog.no_slope_reason(dict(t, unbiased=False)) == "biased/consistent"
    meta = {"configurations": [{"label": "a", "integrator": "vcm", "resolved_parameters": "{mode: bpt, rr: true}"},
                               {"label": "b", "integrator": "vcm", "resolved_parameters": "{mode: bpm}"},
                               {"label": "c", "integrator": "sppm", "unbiased": True}]}
    assert runlog.unbiased("a", "vcm", meta) and not runlog.unbiased("b", "vcm", meta)
    assert runlog.unbiased("c", "sppm", meta), "meta.json's word wins"
    assert not runlog.unbiased("x", "irradiance_cache", None) and runlog.unbiased("x", "bdpt", None)
    assert math.isclose(runlog.slope([(1, 1), (4, 0.5), (16, 0.25)]), -0.5)


def test_keeps_what_the_runner_test_reads(report):
    """tests/experiments/runner_test.cpp counts the report's <img src=' tags:
    three plots, and per row of the grid the image and error image, full
    frame and crop (the reference: image and crop)."""
    _, text = report
    assert text.count("<img src='") == 3 + 2 + 4 * len(CONFIGS)


# ---- parameter sweeps ---------------------------------------------------------

# A plain configuration and a sweep of three members, labelled as the runner
# expands `{label: SPPM, integrator: sppm, sweep: {relative_radius: [...]}}`.
GROUP = "SPPM"
RADII = [0.005, 0.01, 0.08]
SWEEP_CONFIGS = [("PT", "path")] + [(f"{GROUP} relative_radius={r:g}", "sppm") for r in RADII]
SWEEPS = {l: (GROUP, {"relative_radius": r}) for (l, _), r in zip(SWEEP_CONFIGS[1:], RADII)}


def colormap_colours(name):
    cmap = matplotlib.pyplot.get_cmap(name)
    return {matplotlib.colors.to_hex(cmap(i)) for i in range(cmap.N)}


def test_sweep_members_share_one_colormap():
    labels = [l for l, _ in SWEEP_CONFIGS] + ["other"]
    group_of = {l: g for l, (g, _) in SWEEPS.items()}
    colour = plots.assign_colours(labels, group_of)
    family = plots.sweep_colormaps([GROUP])[GROUP]
    members = [colour[l] for l in SWEEPS]
    assert all(c in colormap_colours(family) for c in members), (family, members)
    assert len(set(members)) == len(members), "each member its own shade"
    for plain in ("PT", "other"):
        assert colour[plain] not in colormap_colours(family) and colour[plain] not in members
    assert colour["PT"] != colour["other"]
    # Lighter to darker in the experiment's order.
    lum = [sum(matplotlib.colors.to_rgb(c)) for c in members]
    assert lum == sorted(lum, reverse=True), lum
    # Two sweeps: two families; without sweeps, tab10 in order as before.
    two = plots.assign_colours(["a x=1", "a x=2", "b y=1", "b y=2"], {"a x=1": "a", "a x=2": "a", "b y=1": "b",
                                                                      "b y=2": "b"})
    maps = plots.sweep_colormaps(["a", "b"])
    assert maps["a"] != maps["b"] and two["b y=1"] in colormap_colours(maps["b"])
    tab10 = [matplotlib.colors.to_hex(c) for c in matplotlib.pyplot.get_cmap("tab10").colors]
    assert list(plots.assign_colours(["p", "q", "r"]).values()) == tab10[:3]


def test_sweep_members_key_order_follows_the_label():
    """meta.json's objects have their keys sorted; the label keeps the
    experiment file's order, and the first key is the plot's x axis."""
    label = "SPPM relative_radius=0.005, alpha=0.5"
    meta = {"configurations": [{"label": "PT"}, {"label": label, "sweep": {
        "group": "SPPM", "values": {"alpha": 0.5, "relative_radius": 0.005}}}]}
    sweeps = runlog.sweep_members(["PT", label], meta)
    assert list(sweeps) == ["SPPM"] and list(sweeps["SPPM"][0][1]) == ["relative_radius", "alpha"]
    assert runlog.member_name(label, "SPPM") == "relative_radius=0.005, alpha=0.5"
    assert runlog.sweep_members(["PT", label], None) == {}


def fake_table(labels, unbiased=()):
    return {l: dict(no_slope=None if l in unbiased else "biased/consistent", unbiased=l in unbiased,
                    slope_rmse=-0.5, slope_relmse=-1.0) for l in labels}


def test_legend_puts_a_sweep_under_its_group():
    labels = [l for l, _ in SWEEP_CONFIGS]
    sweeps = {GROUP: [(l, v) for l, (_, v) in SWEEPS.items()]}
    colour = plots.assign_colours(labels, {l: GROUP for l in SWEEPS})
    blocks = plots.legend_blocks(labels, fake_table(labels, ["PT"]), colour, 0.01, 2, ["rmse"], sweeps)
    heads = [b for b in blocks if b[0].get_gid() == "sweep-group"]
    assert len(heads) == 1
    block = heads[0]
    assert block[0].get_label() == f"{GROUP}: sweep over relative_radius"
    assert [h.get_color() for h in block[1:]] == [colour[l] for l in SWEEPS]
    assert [h.get_label().split("  ")[0] for h in block[1:]] == [f"relative_radius={r:g}" for r in RADII]
    assert blocks[0][0].get_label().startswith("PT  (slope RMSE -0.50)")
    # Laid out in three columns, the sweep is not split between two of them.
    handles, rows = plots.pack_legend(blocks, 3)
    assert len(handles) == 3 * rows
    at = handles.index(block[0])
    assert handles[at:at + len(block)] == block and at // rows == (at + len(block) - 1) // rows, (at, rows)


def test_sweep_plot_lines_and_axes():
    """Two keys: one line per value of the last key against the first; a log
    x axis where the values span over 10x; min-max error bars."""
    members, labels = [], {}
    for i, r in enumerate([0.001, 0.01, 0.1]):
        for j, a in enumerate([0.5, 0.7]):
            label = f"S r={r:g}, a={a:g}"
            members.append((label, {"r": r, "a": a}))
            labels[label] = {rep: [dict(rmse=0.1 + 0.01 * i + 0.02 * j + 0.005 * rep)] for rep in range(2)}
    fig, ax = matplotlib.pyplot.subplots()
    colour = plots.assign_colours(list(labels), {l: "S" for l in labels})
    plots.plot_sweep(ax, "box", "S", members, labels, colour, "Blues")
    assert ax.get_xscale() == "log" and ax.get_xlabel() == "r"
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["a=0.5", "a=0.7"]
    bars = [c for c in ax.containers if isinstance(c, matplotlib.container.ErrorbarContainer)]
    assert len(bars) == 2
    ys = sorted(bars[0].lines[0].get_ydata())
    assert np.allclose(ys, [0.1025, 0.1125, 0.1225])  # the mean over the two repeats
    matplotlib.pyplot.close(fig)


@pytest.fixture(scope="module")
def sweep_report(tmp_path_factory):
    run_dir = str(tmp_path_factory.mktemp("sweep") / "run with sweep")
    write_run(run_dir, structured=True, configs=SWEEP_CONFIGS, sweeps=SWEEPS)
    run_report(run_dir)
    with open(os.path.join(run_dir, "report.html"), encoding="utf-8") as f:
        return run_dir, f.read()


def test_report_plots_and_names_a_sweep(sweep_report):
    run_dir, text = sweep_report
    plot = os.path.join(run_dir, f"{SCENE}__sweep-sppm.png")
    assert os.path.exists(plot) and os.path.exists(plot[:-4] + ".svg")
    assert "<h3>Parameter sweeps</h3>" in text and f"Sweep <b>{GROUP}</b>: 3 configurations" in text
    assert "against relative_radius (0.005, 0.01, 0.08)" in text
    # One more plot than a run without sweeps; still one grid row per configuration.
    assert text.count("<img src='") == 3 + 1 + 2 + 4 * len(SWEEP_CONFIGS)
    rows = re.findall(r"<div class='rowlabel'>.*?<b>(.*?)</b>", text)
    assert rows == ["reference"] + [l for l, _ in SWEEP_CONFIGS]
    # The legends of the drawn figures (SVG text, svg.fonttype none) name the
    # group, list each member by its values after it, and draw the members
    # in their colormap's shades and PT in a colour of its own.
    with open(os.path.join(run_dir, f"{SCENE}__convergence.svg"), encoding="utf-8") as f:
        svg = f.read()
    head = svg.index(f"{GROUP}: sweep over relative_radius")
    assert all(svg.index(f"relative_radius={r:g}  (", head) > head for r in RADII)
    strokes = set(re.findall(r"stroke: (#[0-9a-f]{6})", svg))
    family = colormap_colours(plots.sweep_colormaps([GROUP])[GROUP])
    assert len(strokes & family) >= 3, strokes
    swatches = dict(re.findall(r"background-color:(#[0-9a-f]{6})'></span><b>(.*?)</b>", text))
    by_label = {v: k for k, v in swatches.items()}
    assert all(by_label[l] in family for l in SWEEPS) and by_label["PT"] not in family


def test_runs_without_sweeps_add_no_sweep_plot(report):
    path, text = report
    assert "Parameter sweeps" not in text
    assert not [f for f in os.listdir(os.path.dirname(path)) if "__sweep-" in f]


def test_reference_exr_is_found_in_the_cache(tmp_path):
    run_dir = tmp_path / "res ults" / "exp" / "run 1"
    (tmp_path / "res ults" / "references").mkdir(parents=True)
    run_dir.mkdir(parents=True)
    for name in ("box-abc123.exr", "box-abc123.variance.exr", "box-other.exr"):
        (tmp_path / "res ults" / "references" / name).write_bytes(b"")
    path, _ = images.reference_exr(str(run_dir), {"reference": "abc123"}, {})
    assert path == str(tmp_path / "res ults" / "references" / "box-abc123.exr")
    path, where = images.reference_exr(str(run_dir), {"reference": "nothere"}, {})
    assert path is None and "nothere" in where


def test_slug_is_the_programs():
    """The report finds images by the names the runner gave them."""
    import lightbench
    for label in ("PT: NEE + MIS power", "SPPM relative_radius=0.01, alpha=0.5", "Üben 2×", "a/b\\c"):
        assert runlog.slug(label) == lightbench._core.slug(label), label


def test_runs_timed_on_different_kinds_of_machine_are_refused_unless_asked(tmp_path):
    """An MPI sweep over a mixed cluster (issue 19): the log's cpu and threads
    columns differ between runs of one scene; equal-time comparisons would be
    wrong, so the report refuses (exit 3) until --mixed-machines is given.
    Only the host differing (identical nodes) is fine."""
    run_dir = str(tmp_path / "mixed")
    write_run(run_dir, with_meta=False)
    log = os.path.join(run_dir, "log.csv")
    with open(log, newline="") as f:
        rows = list(csv.DictReader(f))

    def rewrite(kind):
        fields = list(rows[0].keys())[:-1] + ["host", "cpu", "threads", "final"]
        with open(log, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=fields)
            w.writeheader()
            for r in rows:
                w.writerow({**r, **kind(r)})

    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    report = lambda *extra: subprocess.run(["/usr/bin/python3", REPORT, run_dir, *extra], capture_output=True,
                                           text=True, timeout=60, env=env)
    rewrite(lambda r: {"host": f"node{r['repeat']}", "cpu": "Xeon, 2.2GHz", "threads": "8"})
    assert report().returncode == 0
    rewrite(lambda r: {"host": "n", "cpu": "Xeon, 2.2GHz" if r["label"] == CONFIGS[0][0] else "EPYC", "threads": "8"})
    os.remove(os.path.join(run_dir, "rmse_vs_time.png"))
    refused = report()
    assert refused.returncode == 3
    assert "2 kinds of machine" in refused.stderr and "--mixed-machines" in refused.stderr
    assert not os.path.exists(os.path.join(run_dir, "rmse_vs_time.png"))
    assert report("--mixed-machines").returncode == 0
    rewrite(lambda r: {"host": "n", "cpu": "EPYC", "threads": "8" if r["repeat"] == "0" else "4"})
    assert report().returncode == 3


def test_final_table_ranked_rows_have_the_headers_columns(tmp_path):
    """docs/results.md's tables come from final_table.py --ranked: a row or
    separator with another cell count than the header is not a table."""
    run_dir = str(tmp_path / "run")
    write_run(run_dir, tied=True)
    script = os.path.join(os.path.dirname(REPORT), "final_table.py")
    p = subprocess.run(["/usr/bin/python3", script, run_dir, "--ranked"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    rows = [line for line in p.stdout.splitlines() if line.startswith("|")]
    assert len(rows) == 2 + len(CONFIGS)
    cells = [line.count("|") for line in rows]
    assert cells == [cells[0]] * len(rows), p.stdout
    assert "(tied)" in p.stdout
