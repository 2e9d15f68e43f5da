"""The program as a user types it (issue 15): self-describing integrators,
--resolution, --exposure, --aov layers and EXR metadata, -o NAME.png, the
wrong subcommand, and bash completion."""
import subprocess

import matplotlib.image
import numpy as np
import pytest

import lightbench


def run(binary, *args, check=True):
    p = subprocess.run([binary, *map(str, args)], capture_output=True, text=True)
    if check and p.returncode != 0:
        raise AssertionError(f"exit {p.returncode}: {p.stderr}")
    return p


def test_integrators_name_lists_every_key_with_type_default_and_range(binary):
    out = run(binary, "integrators", "sppm").stdout
    for k in lightbench.integrator_keys("sppm"):
        line = next(l for l in out.splitlines() if l.split()[:1] == [k["key"]])
        assert k["type"] in line and k["default"] in line and k["allowed"] in line and k["meaning"] in line
    assert "alpha" in out and "(0, 1)" in out
    assert len(run(binary, "integrators").stdout.splitlines()) == len(lightbench.integrators())
    p = run(binary, "integrators", "spm", check=False)
    assert p.returncode == 2 and "did you mean 'sppm'" in p.stderr


def test_resolution_exposure_and_png_only_output(binary, small_scene, tmp_path):
    exr = tmp_path / "r.exr"
    run(binary, "render", small_scene, "--spp", 2, "--resolution", "40x30", "-q", "-o", exr)
    assert lightbench.read_exr(exr).shape == (30, 40, 3)
    p = run(binary, "render", small_scene, "--spp", 1, "--resolution", "40by30", check=False)
    assert p.returncode == 2 and "--resolution: must be WIDTHxHEIGHT" in p.stderr and p.stderr.count("\n") == 1
    # -o NAME.png writes the preview (at the exposure asked) and says so; no EXR.
    png = tmp_path / "bright.png"
    p = run(binary, "render", small_scene, "--spp", 2, "--exposure", 1, "-q", "-o", png)
    assert "preview only" in p.stderr
    assert png.exists() and (tmp_path / "bright.config.yaml").exists() and not (tmp_path / "bright.exr").exists()
    dark = matplotlib.image.imread(tmp_path / "r.png")
    run(binary, "render", small_scene, "--spp", 2, "--resolution", "40x30", "--exposure", 1, "-q", "-o", png)
    assert matplotlib.image.imread(png).mean() > dark.mean() * 1.2  # one stop brighter (clipped, sRGB)


def test_aov_layers_and_metadata_in_one_exr(binary, small_scene, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    exr = out / "layers.exr"
    # BDPT's weighted strategy images up to the path length cover every
    # strategy: they sum to the image (Veach 1997, Fig. 10.3).
    run(binary, "render", small_scene, "--integrator", "bdpt", "--set", "max_depth=3", "--set", "strategy_images=3",
        "--spp", 4, "--seed", 5, "--aov", "albedo,normal,depth,variance,spp", "--resolution", "48x48", "-q", "-o", exr)
    assert sorted(p.name for p in out.iterdir()) == ["layers.config.yaml", "layers.exr", "layers.png"]  # one EXR
    image = lightbench.read_exr(exr)
    meta = lightbench.read_exr_metadata(exr)
    assert meta["lightbench/integrator"] == "bdpt" and meta["lightbench/spp"] == "4" and meta["lightbench/seed"] == "5"
    assert "strategy_images: 3" in meta["lightbench/parameters"]
    assert np.all(lightbench.read_exr_layer(exr, "spp") == 4)
    assert np.all(lightbench.read_exr_layer(exr, "variance") >= 0)
    assert lightbench.read_exr_layer(exr, "depth").max() > 0
    normal = lightbench.read_exr_layer(exr, "normal")
    # Unit length inside a surface; pixels on an edge average two normals.
    assert np.median(np.linalg.norm(normal, axis=2)) == pytest.approx(1, abs=1e-4)
    total = np.zeros_like(image)
    for length in (1, 2, 3):
        for t in range(1, length + 2):
            s = length + 1 - t
            if (s, t) == (1, 1):
                continue
            total += lightbench.read_exr_layer(exr, f"s{s}_t{t}")
    assert np.allclose(total, image, rtol=1e-5, atol=1e-6)
    assert not np.allclose(total - lightbench.read_exr_layer(exr, "s0_t2"), image)  # each layer matters


def test_the_wrong_subcommand_is_named(binary, small_scene, source_dir):
    p = run(binary, "render", source_dir / "experiments" / "quickstart.yaml", check=False)
    assert p.returncode == 2 and "lightbench run" in p.stderr and p.stderr.count("\n") == 1
    p = run(binary, "run", small_scene, check=False)
    assert p.returncode == 2 and "lightbench render" in p.stderr and p.stderr.count("\n") == 1


@pytest.mark.parametrize("words, expected", [
    (["lightbench", "re"], "render"),
    (["lightbench", "render", "--integ"], "--integrator"),
    (["lightbench", "render", "--integrator", "sp"], "sppm"),
    (["lightbench", "render", "--set", "max_d"], "max_depth="),
    (["lightbench", "integrators", "v"], "vcm"),
])
def test_bash_completion(binary, words, expected):
    script = run(binary, "completion", "bash").stdout
    cword = len(words) - 1
    probe = (f"{script}\nCOMP_WORDS=({' '.join(words)}); COMP_CWORD={cword}; _lightbench; "
             'printf "%s\\n" "${COMPREPLY[@]}"')
    out = subprocess.run(["bash", "-c", probe], capture_output=True, text=True, check=True).stdout.split()
    assert expected in out, out


def region_z_scores(a, var_a, b, var_b, regions=4):
    """z of the difference of region means, the variance of each mean from the
    films' per-pixel variance of the estimate (independent pixels)."""
    h, w, _ = a.shape
    zs = []
    for i in range(regions):
        for j in range(regions):
            ys, xs = slice(i * h // regions, (i + 1) * h // regions), slice(j * w // regions, (j + 1) * w // regions)
            n = a[ys, xs].shape[0] * a[ys, xs].shape[1]
            diff = a[ys, xs].reshape(-1, 3).mean(0) - b[ys, xs].reshape(-1, 3).mean(0)
            var = (var_a[ys, xs].reshape(-1, 3).sum(0) + var_b[ys, xs].reshape(-1, 3).sum(0)) / n ** 2
            zs.extend(diff / np.sqrt(np.maximum(var, 1e-30)))
    return np.array(zs)


@pytest.mark.parametrize("integrator", ["path", "light", "bdpt"])
def test_a_crop_window_estimates_the_same_pixels(small_scene, integrator):
    """render --crop: the window's pixels estimate what they do in the full
    render (the camera's importance is renormalised over the window: light
    tracing and BDPT's t = 1 strategies splat through it)."""
    from statistics import NormalDist
    window = (12, 4, 28, 20)  # 16 x 16 pixels of a 32 x 24 film
    full = lightbench.render(small_scene, integrator=integrator, spp=4096, seed=1, aovs=["variance"],
                             resolution=(32, 24))
    crop = lightbench.render(small_scene, integrator=integrator, spp=4096, seed=2, aovs=["variance"],
                             resolution=(32, 24), crop=window)
    assert crop.shape == (16, 16, 3)
    x0, y0, x1, y1 = window
    z = region_z_scores(crop, crop.layers["variance"], full[y0:y1, x0:x1], full.layers["variance"][y0:y1, x0:x1])
    critical = NormalDist().inv_cdf(1 - (1 - (1 - 1e-3) ** (1 / len(z))) / 2)  # Šidák over regions and channels
    assert np.abs(z).max() < critical, (np.abs(z).max(), critical)


def test_a_crop_outside_the_film_is_refused(binary, small_scene):
    p = run(binary, "render", small_scene, "--spp", 1, "--crop", "0,0,25,10", check=False)
    assert p.returncode == 2 and "'--crop'" in p.stderr and "not inside the 24x16 film" in p.stderr
    p = run(binary, "render", small_scene, "--spp", 1, "--crop", "5,0,5,10", check=False)
    assert p.returncode == 2 and "--crop" in p.stderr
