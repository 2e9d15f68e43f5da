"""Issue 34 on the Python side: render()'s arguments go through the same
checks as `lightbench render`'s flags (no truncation, no wrap-around), metrics
of no pixels are refused, load_run drops a torn last row as --resume does, and
Ctrl-C stops a render between passes."""
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import lightbench


@pytest.mark.parametrize("kwargs, argument, phrase", [
    ({"threads": -1}, "threads", "got '-1'"),
    ({"seed": -1}, "seed", "got '-1'"),
    ({"seed": 2.5}, "seed", "got '2.5'"),
    ({"spp": 1.5}, "spp", "got '1.5'"),
    ({"seconds": float("nan")}, "seconds", "got 'nan'"),
    ({"seconds": 1e300}, "seconds", "must be at most 2592000"),
    ({"resolution": (8.5, 8)}, "resolution", "got '8.5x8'"),
    ({"crop": (0, 0, 4.5, 4)}, "crop", "got '0,0,4.5,4'"),
    ({"crop": (0, 0, 4)}, "crop", "expected 4 numbers"),
])
def test_render_arguments_are_checked_as_the_flags_are(small_scene, kwargs, argument, phrase):
    args = {"spp": 1, **kwargs} if "seconds" not in kwargs else kwargs
    with pytest.raises(lightbench.ConfigError) as e:
        lightbench.render(small_scene, **args)
    assert f"render(): '{argument}'" in str(e.value) or f"render(): {argument}" in str(e.value), str(e.value)
    assert phrase in str(e.value)


def test_whole_numbers_of_any_integer_type_are_accepted(small_scene):
    image = lightbench.render(small_scene, spp=np.int64(1), seed=np.uint64(3), threads=1,
                              resolution=(np.int32(8), 6), crop=(0, 0, 4, 4))
    assert image.shape == (4, 4, 3)


def test_metrics_of_no_pixels_are_refused():
    empty = np.zeros((0, 0, 3), np.float32)
    with pytest.raises(ValueError, match="no pixels"):
        lightbench.rmse(empty, empty)


def test_load_run_drops_a_torn_last_row(tmp_path, small_scene):
    exp = tmp_path / "e.yaml"
    exp.write_text(f"""
scenes:
  - {{scene: "{small_scene}", reference: {{integrator: path, spp: 4}}}}
configurations:
  - {{label: "PT", integrator: path}}
budget: {{spp: 2}}
snapshots: {{count: 2, spacing: linear}}
""")
    run_dir = lightbench.run_experiment(exp, results=str(tmp_path / "results"), report=False)
    log = os.path.join(run_dir, "log.csv")
    text = open(log).read()
    with open(log, "w") as f:
        f.write(text[:-4])  # the final row without its last field's end, as a kill mid-write leaves it
    run = lightbench.load_run(run_dir)
    assert len(run.log) == 1 and not run.log["final"].any()


def test_load_run_refuses_a_row_torn_before_the_last_and_a_file_that_is_no_log(tmp_path, small_scene):
    # As --resume refuses them (issue 34, class 10): pandas padded the torn
    # row with NaN, and random bytes raised a pandas error.
    exp = tmp_path / "e.yaml"
    exp.write_text(f"""
scenes:
  - {{scene: "{small_scene}", reference: {{integrator: path, spp: 4}}}}
configurations:
  - {{label: "PT", integrator: path}}
budget: {{spp: 2}}
snapshots: {{count: 2, spacing: linear}}
""")
    run_dir = lightbench.run_experiment(exp, results=str(tmp_path / "results"), report=False)
    log = os.path.join(run_dir, "log.csv")
    lines = open(log).read().splitlines(keepends=True)
    assert len(lines) == 3
    with open(log, "w") as f:
        f.write(lines[0] + lines[1][: len(lines[1]) // 2] + "\n" + lines[2])
    with pytest.raises(lightbench.ConfigError, match=r"log\.csv:2: a row of"):
        lightbench.load_run(run_dir)
    with open(log, "wb") as f:
        f.write(bytes(range(256)))
    with pytest.raises(lightbench.ConfigError, match=r"log\.csv:1: not a lightbench log"):
        lightbench.load_run(run_dir)


def test_ctrl_c_stops_a_render_with_keyboard_interrupt(small_scene, tmp_path):
    script = tmp_path / "long.py"
    script.write_text(textwrap.dedent(f"""
        import sys, lightbench
        print("start", flush=True)
        try:
            lightbench.render({str(small_scene)!r}, seconds=120, threads=1)
        except KeyboardInterrupt:
            print("interrupted", flush=True)
            sys.exit(3)
        print("finished", flush=True)
    """))
    p = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, text=True, env=os.environ.copy())
    assert p.stdout.readline().strip() == "start"
    time.sleep(3)  # into the passes
    p.send_signal(signal.SIGINT)
    try:
        out, _ = p.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        p.kill()
        pytest.fail("the render did not stop within 30 s of Ctrl-C")
    assert p.returncode == 3 and "interrupted" in out, out
