"""MPI runs on one machine (issue 19): `mpirun --oversubscribe -np 3` against
a single process. Registered by tests/CMakeLists.txt only in an MPI build.

  * an experiment on 3 ranks logs the same rows (apart from timings and where
    they were taken) and writes the same images, bit for bit, as one process;
  * the reference its workers rendered in chunks is bit-identical;
  * a worker killed mid-experiment fails the job with rank 0's log intact, and
    --resume (on 2 ranks, then alone) completes it;
  * `render --distributed` gives the same bits on 1 and 3 ranks, and refuses
    integrators whose passes cannot be split.
"""
import csv
import filecmp
import os
import pathlib
import signal
import subprocess
import time

import numpy as np
import pytest
from lightbench import read_exr  # this build's package (PYTHONPATH)

SOURCE_DIR = pathlib.Path(os.environ.get("LIGHTBENCH_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BINARY = os.environ.get("LIGHTBENCH_BINARY", str(SOURCE_DIR / "build" / "lightbench"))
MPIRUN = os.environ.get("LIGHTBENCH_MPIEXEC", "mpirun")
TINY = SOURCE_DIR / "tests" / "data" / "mpi-tiny.yaml"
# Where a row was timed, and how long it took: the only columns that may differ.
WHERE_AND_WHEN = ("time_s", "preprocess_s", "over_budget_s", "host", "cpu", "threads")


def mpirun(n, *args, **kw):
    # Root in CI containers; --oversubscribe: 3 ranks on 2 cores.
    cmd = [MPIRUN, "--allow-run-as-root", "--oversubscribe", "-np", str(n), BINARY, *map(str, args)]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=600, **kw)


def single(*args, **kw):
    return subprocess.run([BINARY, *map(str, args)], capture_output=True, text=True, timeout=600, **kw)


def run_dir(results, name):
    runs = sorted((pathlib.Path(results) / name).iterdir())
    assert len(runs) == 1, runs
    return runs[0]


def log_rows(folder):
    with open(folder / "log.csv", newline="") as f:
        return list(csv.DictReader(f))


def comparable(rows):
    return sorted(tuple(sorted((k, v) for k, v in r.items() if k not in WHERE_AND_WHEN)) for r in rows)


def test_three_ranks_write_what_one_process_writes(tmp_path):
    one = single("run", TINY, "--results", tmp_path / "one", "--no-report")
    assert one.returncode == 0, one.stderr
    three = mpirun(3, "run", TINY, "--results", tmp_path / "three", "--no-report")
    assert three.returncode == 0, three.stderr
    assert "on 2 MPI worker rank(s)" in three.stderr
    a, b = run_dir(tmp_path / "one", "mpi-tiny"), run_dir(tmp_path / "three", "mpi-tiny")

    rows_a, rows_b = log_rows(a), log_rows(b)
    assert len(rows_a) == 3 * 2 * 3 + 2 * 3  # 3 configurations x 2 repeats x 3 snapshots, + bdpt's denoised rows
    assert comparable(rows_a) == comparable(rows_b)
    # Both ranks did some of the work, and every row says where.
    assert {r["host"] for r in rows_b} == {os.uname().nodename}
    assert {r["threads"] for r in rows_b} == {"1"}  # 2 cores shared by 2 worker ranks

    names = sorted(p.name for p in a.iterdir() if p.is_file() and p.name != "meta.json")
    assert names == sorted(p.name for p in b.iterdir() if p.is_file() and p.name != "meta.json")
    images = [n for n in names if n.endswith((".exr", ".png"))]
    assert len(images) > 20
    for name in images + ["decomposition.csv"]:
        assert filecmp.cmp(a / name, b / name, shallow=False), name

    # The reference the two workers rendered in four chunks, reduced in chunk
    # order on rank 0: the same bytes as the one rendered here.
    refs = sorted((tmp_path / "one" / "references").glob("*.exr"))
    assert len(refs) == 2  # the mean and its variance
    for ref in refs:
        other = tmp_path / "three" / "references" / ref.name
        assert filecmp.cmp(ref, other, shallow=False), ref.name
    assert "chunks of 16 spp" in three.stderr


def worker_pids(rank):
    """Processes of this binary that Open MPI started as `rank`."""
    pids = []
    for proc in pathlib.Path("/proc").iterdir():
        if not proc.name.isdigit():
            continue
        try:
            if os.path.realpath(proc / "exe") != os.path.realpath(BINARY):
                continue
            env = (proc / "environ").read_bytes().split(b"\0")
        except OSError:
            continue
        if f"OMPI_COMM_WORLD_RANK={rank}".encode() in env:
            pids.append(int(proc.name))
    return pids


def test_a_killed_rank_fails_the_job_and_resume_completes_it(tmp_path):
    # Runs of 1 s each, so the kill lands mid-experiment: 3 configurations x 2
    # repeats over 2 workers is about 3 s of work.
    experiment = tmp_path / "killed.yaml"
    experiment.write_text(TINY.read_text().replace("../../scenes/", str(SOURCE_DIR / "scenes") + "/")
                          .replace("budget: {spp: 8}", "budget: {seconds: 1}"))
    results = tmp_path / "results"
    cmd = [MPIRUN, "--allow-run-as-root", "--oversubscribe", "-np", "3", BINARY, "run", str(experiment),
           "--results", str(results), "--no-report"]
    job = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    log = None
    deadline = time.time() + 120
    while time.time() < deadline:
        logs = list(results.glob("killed/*/log.csv"))
        if logs and any(r["final"] == "1" for r in log_rows(logs[0].parent)):
            log = logs[0]
            break
        time.sleep(0.05)
    assert log is not None, "no run finished"
    victims = worker_pids(2)
    assert victims, "rank 2 not found"
    for pid in victims:
        os.kill(pid, signal.SIGKILL)
    _, err = job.communicate(timeout=120)
    assert job.returncode != 0, err

    # Rank 0's log is intact: every line whole, and at least one run finished
    # but not all of them.
    folder = log.parent
    rows = log_rows(folder)
    assert all(len(r) == len(rows[0]) and None not in r.values() for r in rows)
    finished = {(r["label"], r["repeat"]) for r in rows if r["final"] == "1" and " + " not in r["label"]}
    assert 1 <= len(finished) < 6, finished

    # --resume on two ranks redoes only the unfinished runs.
    resumed = mpirun(2, "run", experiment, "--results", results, "--no-report", "--resume")
    assert resumed.returncode == 0, resumed.stderr
    assert f"resume: {len(finished)} of 6 runs already complete" in resumed.stderr
    rows = log_rows(folder)
    assert sorted((r["label"], r["repeat"]) for r in rows if r["final"] == "1" and " + " not in r["label"]) == sorted(
        (label, str(rep)) for label in ("path", "light", "bdpt") for rep in (0, 1))
    assert run_dir(results, "killed") == folder
    # And alone, with nothing left to do, it only rewrites the report's inputs.
    again = single("run", experiment, "--results", results, "--no-report", "--resume")
    assert again.returncode == 0, again.stderr
    assert "resume: 6 of 6 runs already complete" in again.stderr


def test_distributed_render_has_the_same_bits_on_any_number_of_ranks(tmp_path):
    scene = SOURCE_DIR / "scenes" / "cornell-box.yaml"
    common = ["render", scene, "--resolution", "40x30", "--spp", "32", "--distributed", "--integrator", "bdpt",
              "--seed", "3", "-q", "--chunk-spp"]
    one = single(*common, "4", "-o", tmp_path / "one.exr")
    assert one.returncode == 0, one.stderr
    three = mpirun(3, *common, "4", "-o", tmp_path / "three.exr")
    assert three.returncode == 0, three.stderr
    # The pixels (the headers differ: they record the seconds taken).
    assert np.array_equal(read_exr(tmp_path / "one.exr"), read_exr(tmp_path / "three.exr"))
    assert filecmp.cmp(tmp_path / "one.png", tmp_path / "three.png", shallow=False)
    assert "ranks: 3" in (tmp_path / "three.config.yaml").read_text()
    # A different split is a different (equally valid) estimate: the chunk size is part of the promise.
    other = single(*common, "8", "-o", tmp_path / "eight.exr")
    assert other.returncode == 0, other.stderr
    assert not np.array_equal(read_exr(tmp_path / "one.exr"), read_exr(tmp_path / "eight.exr"))


@pytest.mark.parametrize("integrator,why", [("sppm", "radii"), ("mlt", "Markov"), ("vcm", "merging radius")])
def test_distributed_render_refuses_what_cannot_be_split(tmp_path, integrator, why):
    r = mpirun(2, "render", SOURCE_DIR / "scenes" / "cornell-box.yaml", "--resolution", "16x16", "--spp", "8",
               "--distributed", "--integrator", integrator, "-o", tmp_path / "x.exr")
    assert r.returncode == 2
    lines = [l for l in r.stderr.splitlines() if l.startswith("error:")]
    assert len(lines) == 1 and "'--distributed'" in lines[0] and why in lines[0], r.stderr
    assert not list(tmp_path.iterdir())


def test_bad_input_under_mpi_is_one_line_from_rank_0(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text(TINY.read_text().replace("../../scenes/", str(SOURCE_DIR / "scenes") + "/")
                   .replace("integrator: light}", "integrator: lihgt}"))
    r = mpirun(3, "run", bad, "--results", tmp_path / "results", "--no-report")
    assert r.returncode == 2
    lines = [l for l in r.stderr.splitlines() if l.startswith("error:")]
    assert len(lines) == 1 and "bad.yaml:" in lines[0], r.stderr
    assert not (tmp_path / "results" / "bad").exists()


def test_a_workers_note_waits_for_its_first_task(tmp_path):
    """Issue 34, class 8: a worker bound to fewer cores than its share says
    so, but only once it has work: for bad input rank 0's error is the only
    line lightbench prints. The good run shows the note does appear under
    this binding (two ranks bound to one core each, one worker with a share
    of two), so the test can fail."""
    tiny = TINY.read_text().replace("../../scenes/", str(SOURCE_DIR / "scenes") + "/")
    def bound(experiment, results):
        return subprocess.run([MPIRUN, "--allow-run-as-root", "--bind-to", "core", "-np", "2", BINARY, "run",
                               str(experiment), "--results", str(results), "--no-report"],
                              capture_output=True, text=True, timeout=600)
    good = tmp_path / "good.yaml"
    good.write_text(tiny)
    r = bound(good, tmp_path / "results")
    assert r.returncode == 0, r.stderr
    if os.cpu_count() < 2 or "note: may use 1 of" not in r.stderr:
        pytest.skip("mpirun did not bind the worker to fewer cores than its share here")
    bad = tmp_path / "bad.yaml"
    bad.write_text(tiny.replace("integrator: light}", "integrator: lihgt}"))
    r = bound(bad, tmp_path / "results2")
    assert r.returncode == 2
    ours = [l for l in r.stderr.splitlines() if l.startswith("error:") or "note:" in l or l.startswith("[rank")]
    assert len(ours) == 1 and ours[0].startswith("error:") and "bad.yaml:" in ours[0], r.stderr


def test_a_worker_reading_other_files_refuses_its_tasks(tmp_path):
    """Every rank reads the experiment and its scenes itself (a shared file
    system); a rank that sees other bytes (a stale copy on a node) must not
    feed rank 0's results. MPMD launch: rank 0 runs one file, the workers
    another that differs in one seed."""
    ours = tmp_path / "ours.yaml"
    ours.write_text(TINY.read_text().replace("../../scenes/", str(SOURCE_DIR / "scenes") + "/"))
    stale = tmp_path / "stale.yaml"
    stale.write_text(ours.read_text().replace("seed: 5", "seed: 6"))
    results = tmp_path / "results"
    cmd = [MPIRUN, "--allow-run-as-root", "--oversubscribe", "-np", "1", BINARY, "run", str(ours), "--results",
           str(results), "--no-report", ":", "-np", "2", BINARY, "run", str(stale), "--results", str(results),
           "--no-report"]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert r.returncode == 2, r.stderr
    lines = [l for l in r.stderr.splitlines() if l.startswith("error:")]
    assert len(lines) == 1 and "reads another experiment" in lines[0], r.stderr
    # The reference the workers would have rendered is not in the cache.
    assert not list(results.glob("references/*.exr"))
