"""The Python package (python/lightbench) against the program and against the
definitions: a render equals `lightbench render`'s EXR, a run folder reads back
into the log's rows, and the metric functions equal numpy written from the
formulas in experiments/metrics.h."""
import csv
import json
import subprocess

import numpy as np
import pandas as pd
import pytest

import lightbench


def test_render_equals_the_programs_exr_bit_for_bit(small_scene, binary, tmp_path):
    out = tmp_path / "out dir"
    out.mkdir()
    exr = out / "box.exr"
    subprocess.run([binary, "render", str(small_scene), "--integrator", "bdpt", "--set", "mis=balance", "--spp", "4",
                    "--seed", "7", "-q", "-o", str(exr)], check=True, capture_output=True)
    img = lightbench.render(small_scene, integrator="bdpt", params={"mis": "balance"}, spp=4, seed=7)
    assert img.shape == (16, 24, 3) and img.dtype == np.float32
    assert np.array_equal(img, lightbench.read_exr(exr))  # the same code: the same bits
    # A different seed is a different image: the comparison above can fail.
    assert not np.array_equal(img, lightbench.render(small_scene, integrator="bdpt", params={"mis": "balance"},
                                                     spp=4, seed=8))


def test_render_metadata_is_the_resolved_configuration(small_scene):
    img = lightbench.render(small_scene, integrator="sppm", params={"alpha": 0.5, "lookup": "flann"}, spp=2)
    meta = img.metadata
    assert meta["spp"] == 2 and meta["seed"] == 0 and meta["non_finite_samples"] == 0
    assert meta["integrator"]["name"] == "sppm"
    assert meta["integrator"]["alpha"] == 0.5 and meta["integrator"]["lookup"] == "flann"
    assert meta["integrator"]["photons_per_pass"] == 100000  # defaults are resolved too
    assert meta["seconds"] >= meta["preprocess_seconds"] >= 0


def test_bad_parameters_raise_config_error_naming_the_valid_keys(small_scene):
    with pytest.raises(lightbench.ConfigError, match=r"unknown key; did you mean 'alpha'.*valid keys: .*lookup"):
        lightbench.render(small_scene, integrator="sppm", params={"alpah": 0.5}, spp=1)
    with pytest.raises(lightbench.ConfigError, match=r"must be in \(0, 1\)"):
        lightbench.render(small_scene, integrator="sppm", params={"alpha": 1.5}, spp=1)
    for bad in ({"spp": 0}, {"spp": 2.5}, {"seconds": float("inf")}, {"seconds": -1}, {"spp": 1, "seconds": 1}):
        with pytest.raises(ValueError):
            lightbench.render(small_scene, **bad)


def test_metrics_equal_their_definitions():
    rng = np.random.default_rng(3)
    ref = rng.random((9, 13, 3), dtype=np.float32) * 4
    img = ref + rng.normal(0, 0.3, ref.shape).astype(np.float32)
    d = img.astype(np.float64) - ref
    eps = 1e-2
    assert lightbench.rmse(img, ref) == pytest.approx(np.sqrt(np.mean(d * d)), rel=1e-6)
    assert lightbench.relmse(img, ref) == pytest.approx(np.mean(d * d / (ref.astype(np.float64) ** 2 + eps)), rel=1e-6)
    assert lightbench.mape(img, ref) == pytest.approx(100 * np.mean(np.abs(d) / (np.abs(ref) + eps)), rel=1e-6)
    x0, y0, x1, y1 = 2, 3, 7, 8  # [x0, x1) x [y0, y1)
    dc = d[y0:y1, x0:x1]
    assert lightbench.rmse(img, ref, crop=(x0, y0, x1, y1)) == pytest.approx(np.sqrt(np.mean(dc * dc)), rel=1e-6)
    with pytest.raises(ValueError):
        lightbench.rmse(img, ref[:, :5])
    for crop in ((0, 0, 100, 100), (5, 5, 5, 8), (-1, 0, 3, 3)):  # outside, empty, negative
        with pytest.raises(ValueError):
            lightbench.rmse(img, ref, crop=crop)


def test_exr_round_trip(tmp_path):
    a = np.random.default_rng(1).random((5, 7, 3), dtype=np.float32)
    path = tmp_path / "with space.exr"
    lightbench.write_exr(path, a)
    assert np.array_equal(lightbench.read_exr(path), a)


def typed(key):
    """A listed default as the value it spells."""
    text = key["default"]
    if key["type"] == "bool":
        return text == "true"
    if key["type"] == "integer":
        return int(text)
    if key["type"] == "number":
        return float(text)
    return text


def test_integrator_keys_are_what_the_reader_accepts(small_scene):
    keys = {k["key"]: k for k in lightbench.integrator_keys("sppm")}
    assert set(keys) == {"photons_per_pass", "alpha", "initial_radius", "relative_radius", "max_depth", "lookup"}
    assert keys["alpha"]["allowed"] == "(0, 1)" and keys["alpha"]["default"] == "0.7"
    # Every listed key is accepted with its listed default (an unlisted key
    # is not: the test above).
    # Keys read only under a condition ("base: photon", or "rrs: adrrs or ears",
    # of which the first) are given with it, one render per condition (mlt's
    # pssmlt and mmlt keys exclude each other).
    for name in lightbench.integrators():
        keys = lightbench.integrator_keys(name)
        for condition in sorted({k["condition"] for k in keys}):
            params = {k["key"]: typed(k) for k in keys if k["condition"] in ("", condition)}
            if condition:
                key, value = (part.strip() for part in condition.split(":"))
                value = value.split(" or ")[0]
                params[key] = value
            params.update(max_depth=3, global_photons=1000, caustic_photons=1000, photons_per_pass=1000,
                          bootstrap_samples=1000)
            group = {d["key"] for d in keys if d["condition"] in ("", condition)}
            params = {k: v for k, v in params.items() if k in group or (condition and k == key)}
            lightbench.render(small_scene, integrator=name, params=params, spp=1)


def make_experiment(tmp_path, small_scene):
    exp = tmp_path / "tiny experiment.yaml"
    exp.write_text(f"""
scenes:
  - scene: {json.dumps(str(small_scene))}
    reference: {{integrator: path, spp: 64}}
    crop: [4, 4, 12, 12]
configurations:
  - {{label: "PT", integrator: path}}
  - {{label: "light tracing", integrator: light}}
budget: {{spp: 4}}
snapshots: {{count: 2, spacing: linear}}
repeats: 2
seed: 3
""")
    return exp


def test_load_run_reads_the_log_and_images(tmp_path, small_scene):
    exp = make_experiment(tmp_path, small_scene)
    run_dir = lightbench.run_experiment(exp, results=str(tmp_path / "results dir"), report=False)
    run = lightbench.load_run(run_dir)
    with open(f"{run_dir}/log.csv", newline="") as f:  # an independent reader of the same file
        raw = list(csv.DictReader(f))
    assert isinstance(run.log, pd.DataFrame) and len(run.log) == len(raw) == 2 * 2 * 2  # configurations x repeats x snapshots
    assert list(run.log.columns) == list(raw[0].keys())
    assert list(run.log["rmse"]) == pytest.approx([float(r["rmse"]) for r in raw], rel=1e-12)
    assert run.log["final"].dtype == bool and run.final()["repeat"].nunique() == 2
    assert run.meta["configurations"][0]["resolved_parameters"]["mis"] == "power"  # JSON values, not YAML text
    scene = run.meta["scenes"][0]["name"]
    ref = run.references[scene]
    assert ref.shape == (16, 24, 3)
    # The final image of repeat 0 scored with the package's rmse gives the log's value.
    for label in ("PT", "light tracing"):
        row = run.final()[(run.final()["label"] == label) & (run.final()["repeat"] == 0)].iloc[0]
        assert lightbench.rmse(run.images[(scene, label)], ref) == pytest.approx(row["rmse"], rel=1e-6)
        assert lightbench.rmse(run.images[(scene, label)], ref, crop=(4, 4, 12, 12)) == pytest.approx(
            row["rmse_crop"], rel=1e-6)
        # And the trimmed and corrected metrics (the reference's variance from the run folder).
        variance = run.reference_variances[scene]
        assert lightbench.relmse_trimmed(run.images[(scene, label)], ref) == pytest.approx(row["relmse_trimmed"], rel=1e-6)
        assert lightbench.relmse(run.images[(scene, label)], ref, reference_variance=variance) == pytest.approx(
            row["relmse_corrected"], rel=1e-6)
        assert lightbench.rmse(run.images[(scene, label)], ref, reference_variance=variance) == pytest.approx(
            max(0, row["mse_corrected"]) ** 0.5, rel=1e-6)
    # The verdict as a DataFrame: one row per scene and configuration.
    assert list(run.verdict.columns[:8]) == ["scene", "label", "metric", "value", "ci_low", "ci_high", "rank_group",
                                             "decided"]
    assert sorted(run.verdict["label"]) == ["PT", "light tracing"] and set(run.verdict["metric"]) == {"relmse"}
    assert run.verdict["decided"].dtype == bool and run.verdict["rank_group"].dtype == object
    assert (run.verdict["ci_low"] <= run.verdict["value"]).all() and (run.verdict["value"] <= run.verdict["ci_high"]).all()
    assert len(run.verdict_pairs) == 1 and run.verdict_pairs["adjacent"].all()
    assert {"rmse", "relmse", "relmse_trimmed", "rmse_crop"} <= set(run.verdict_metrics["metric"])
