"""lightbench from Python: render scenes, run experiments, read runs into pandas.

    import lightbench
    img = lightbench.render("scenes/cornell-box.yaml", spp=16)   # (H, W, 3) float32
    img.metadata["spp"], img.metadata["integrator"]["name"]
    run_dir = lightbench.run_experiment("experiments/quickstart.yaml", quick=True)
    run = lightbench.load_run(run_dir)        # run.log: DataFrame of log.csv
    lightbench.rmse(run.images[("cornell-box-spheres", "SPPM")], run.references["cornell-box-spheres"])

Rendering, EXR files, the metrics and experiments run the same C++ code as the
`lightbench` program (module lightbench._core): a render here equals
`lightbench render` with the same scene, integrator, parameters and seed, bit
for bit. Bad input raises lightbench.ConfigError (a ValueError) with the same
file:line: key message the program prints.
"""
import json
import numbers
import os

import math

import numpy as np

from . import _core
from ._core import ConfigError  # noqa: F401  (re-exported)
from .metrics import mape, relmse, relmse_trimmed, rmse  # noqa: F401
from .runs import Run, load_run  # noqa: F401

__all__ = ["render", "run_experiment", "load_run", "Run", "read_exr", "read_exr_layer", "read_exr_metadata", "write_exr", "rmse", "relmse", "relmse_trimmed", "mape",
           "integrators", "integrator_keys", "ConfigError", "RenderedImage", "__version__"]
__version__ = _core.version()


class RenderedImage(np.ndarray):
    """A float32 (height, width, 3) array of linear radiance with .metadata:
    the resolved configuration (as `lightbench render` writes to
    <name>.config.yaml: scene, integrator with every parameter, seed, spp,
    seconds, NaN/Inf count) plus preprocess_seconds and rays."""

    def __array_finalize__(self, obj):
        self.metadata = getattr(obj, "metadata", None)
        self.layers = getattr(obj, "layers", {})


def _flag_text(value):
    """A value as typed on the command line: an integer as its digits (numpy's
    too), anything else as str() (2.5 -> "2.5", which a whole-number flag refuses)."""
    if isinstance(value, numbers.Integral) and not isinstance(value, bool):
        return str(int(value))
    return str(value)


def _sequence(value, n, name):
    try:
        values = list(value)
    except TypeError:
        raise ConfigError(f"render(): {name}: expected {n} numbers, got {value!r}") from None
    if len(values) != n:
        raise ConfigError(f"render(): {name}: expected {n} numbers, got {len(values)}")
    return values


def render(scene, integrator=None, params=None, spp=None, seconds=None, seed=0, threads=0, progress=False, aovs=(),
           resolution=None, crop=None):
    """Renders `scene` (a YAML scene, a Mitsuba .xml or a pbrt-v4 .pbrt) and returns a RenderedImage.

    integrator: a name from lightbench.integrators() (default: the scene's, else
    "path"); params: that integrator's keys (dict), checked like the scene's
    (an unknown key raises ConfigError naming the valid ones); spp and/or
    seconds: the budget (neither: the scene's spp, else 16); seed: the same
    seed gives the same image at any thread count; threads: 0 = all cores;
    aovs: any of "albedo", "normal", "depth", "variance", "spp", returned in
    .layers (with the integrator's own layers, e.g. BDPT's strategy images),
    as `lightbench render --aov` writes them into the EXR; resolution:
    (width, height) replaces the scene's film size; crop: (x0, y0, x1, y1)
    renders only that window of the film, [x0, x1) x [y0, y1).
    """
    if spp is not None and seconds is not None:
        raise ValueError("give spp or seconds, not both")
    # Each argument as the command line would carry it, checked by that
    # flag's own check (experiments/cli/flag_checks.h): 2.5, -1 or nan are
    # refused as `--seed 2.5` is, never truncated or wrapped around.
    checks = [("--spp", spp, "spp"), ("--time", seconds, "seconds"), ("--seed", seed, "seed"),
              ("--threads", threads, "threads")]
    for flag, value, name in checks:
        if value is not None:
            _core.check_render_argument(flag, _flag_text(value), name)
    if resolution is not None:
        resolution = "x".join(_flag_text(v) for v in _sequence(resolution, 2, "resolution"))
        _core.check_render_argument("--resolution", resolution, "resolution")
    if crop is not None:
        crop = ",".join(_flag_text(v) for v in _sequence(crop, 4, "crop"))
        _core.check_render_argument("--crop", crop, "crop")
    # Parameters travel as `--set key=value` does, each value as JSON (which
    # YAML reads): one code path for the program and the package.
    overrides = [f"{k}={json.dumps(v)}" for k, v in (params or {}).items()]
    array, resolved, report, layers = _core.render(os.fspath(scene), integrator or "", overrides, int(spp or 0),
                                                   float(seconds or 0), int(seed), int(threads), bool(progress),
                                                   list(aovs),
                                                   resolution or "", crop or "")
    image = array.view(RenderedImage)
    image.metadata = dict(json.loads(resolved), **report)
    image.layers = layers
    return image


def run_experiment(path, quick=False, resume=False, jobs=1, results="results", report=True, python=None):
    """Runs an experiment file as `lightbench run` does; returns the run folder
    (results/<name>/<run-id>), ready for load_run(). python: the report's
    interpreter (as `lightbench run --python`; default $LIGHTBENCH_PYTHON,
    else /usr/bin/python3, which has matplotlib)."""
    return _core.run_experiment(os.fspath(path), bool(quick), bool(resume), int(jobs), os.fspath(results), bool(report),
                                os.fspath(python) if python else "")


def read_exr(path):
    """An EXR's RGB as a float32 (height, width, 3) array (the program's reader)."""
    return _core.read_exr(os.fspath(path))


def read_exr_layer(path, layer):
    """One layer of a layered EXR (e.g. "albedo", "depth", BDPT's "s2_t1"), (H, W, 3)."""
    return _core.read_exr_layer(os.fspath(path), layer)


def read_exr_metadata(path):
    """The EXR header's string attributes (lightbench/integrator, lightbench/spp, ...)."""
    return dict(_core.read_exr_attributes(os.fspath(path)))


def write_exr(path, image):
    """Writes a (height, width, 3) array as a float32 RGB EXR (through a temporary name)."""
    _core.write_exr(os.fspath(path), image)


def integrators():
    """{name: one-line summary} of the registered integrators."""
    return dict(_core.integrator_names())


def integrator_keys(name):
    """The keys integrator `name` reads: a list of dicts with key, type,
    default, allowed, meaning and condition (what `lightbench integrators NAME`
    prints, from the same settings reader)."""
    return _core.integrator_keys(name)
