"""Reading an experiment's run folder (results/<experiment>/<run-id>) into
pandas and numpy: the log, the metadata and the images."""
import csv
import io
import json
import os
from dataclasses import dataclass, field

import pandas as pd

from ._core import ConfigError, read_exr, slug  # slug: a label as in file names (experiments/experiment.h)


@dataclass
class Run:
    folder: str
    log: pd.DataFrame                              # log.csv, one row per snapshot
    meta: dict                                     # meta.json
    images: dict = field(default_factory=dict)     # (scene, label) -> final image of repeat 0, (H, W, 3)
    references: dict = field(default_factory=dict)  # scene -> reference image
    reference_variances: dict = field(default_factory=dict)  # scene -> its per-pixel variance of the mean
    # The verdict (experiments/verdict/run_folder.h): verdict.csv, one row per
    # scene and configuration (rank groups and intervals of the ranked
    # metric); verdict_pairs.csv, every pair's test; verdict_metrics.csv,
    # every metric's corrected value and interval. None without them.
    verdict: pd.DataFrame = None
    verdict_pairs: pd.DataFrame = None
    verdict_metrics: pd.DataFrame = None

    def final(self):
        """The log's final snapshots (one row per scene, configuration and repeat)."""
        return self.log[self.log["final"]]


def _read_log(path):
    """log.csv without a torn last row, as `lightbench run --resume` reads it
    (experiments/run_log.cpp): the runner writes whole lines, so a last line
    without its newline is one a killed run left half written."""
    with open(path, newline="", errors="replace") as f:
        text = f.read()
    if text and not text.endswith("\n"):
        text = text[: text.rfind("\n") + 1]
    # Any other row short of the header's fields (or a file that is not a
    # log at all) is refused, naming the file and line, as --resume refuses
    # it (experiments/run_log.cpp): pandas padded a row torn mid-file with NaN.
    try:
        rows = list(csv.reader(io.StringIO(text)))
    except csv.Error:  # a NUL byte
        rows = []
    # The columns --resume requires (experiments/run_log.cpp), `final` last.
    if not rows or not {"scene", "label", "repeat", "final"} <= set(rows[0]) or rows[0][-1] != "final":
        raise ConfigError(f"{path}:1: not a lightbench log (no scene, label, repeat and final columns, final last)")
    for number, row in enumerate(rows[1:], start=2):
        if len(row) != len(rows[0]):
            raise ConfigError(f"{path}:{number}: a row of {len(row)} fields under a header of {len(rows[0])} "
                              "(a torn or edited row; only the last may be torn, by a killed run)")
    log = pd.read_csv(io.StringIO(text))
    # 1 is final, 0 not; a missing value is not final (astype(bool) made NaN True).
    log["final"] = log["final"] == 1
    return log


def load_run(folder):
    """Reads a run folder: log.csv as a DataFrame (numeric columns typed,
    `final` as bool), meta.json as a dict, and every configuration's final
    image and the references as float32 arrays."""
    folder = os.fspath(folder)
    log = _read_log(os.path.join(folder, "log.csv"))
    meta_path = os.path.join(folder, "meta.json")
    meta = {}
    if os.path.exists(meta_path):
        with open(meta_path) as f:
            meta = json.load(f)
    run = Run(folder, log, meta)
    for name in ("verdict", "verdict_pairs", "verdict_metrics"):
        path = os.path.join(folder, name + ".csv")
        if os.path.exists(path):
            # keep_default_na=False: a rank group "1-2" or an empty reason stays text.
            table = pd.read_csv(path, keep_default_na=False, na_values=[""])
            for column in ("decided", "adjacent"):
                if column in table:
                    table[column] = table[column].astype(str) == "True"
            setattr(run, name, table)
    for scene in meta.get("scenes", []):
        ref = os.path.join(folder, scene.get("reference_exr") or scene["name"] + "__reference.exr")
        if os.path.exists(ref):
            run.references[scene["name"]] = read_exr(ref)
        variance = os.path.join(folder, scene.get("reference_variance_exr") or scene["name"] + "__reference_variance.exr")
        if os.path.exists(variance):
            run.reference_variances[scene["name"]] = read_exr(variance)
    for (scene, label) in log[["scene", "label"]].drop_duplicates().itertuples(index=False):
        path = os.path.join(folder, f"{scene}__{slug(label)}.exr")
        if os.path.exists(path):
            run.images[(scene, label)] = read_exr(path)
    return run
