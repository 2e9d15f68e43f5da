#pragma once
// Verdicts of a run folder (results/<name>/<run-id>/), from what it holds
// alone: meta.json (the labels, crops, the verdict's settings, the
// references' chunk counts), log.csv (final times and the ranked metric's
// curves), every repeat's final EXR and the reference with its variance.
// The runner writes them after each look of a sequential experiment and at
// the end; `lightbench verdict RUN` writes them again, with other settings
// if asked. Files (written to temporary names and renamed):
//   verdict.csv          one row per scene and label, best first:
//                        scene, label, metric, value, ci_low, ci_high,
//                        rank_group, decided, then repeats, raw_value,
//                        time_s, efficiency (+ _low, _high), speedup (over
//                        the baseline, + _low, _high), time_to_target_s
//                        (+ _low_s, _high_s), baseline
//   verdict_pairs.csv    every pair of a scene: the difference (better −
//                        worse, in the metric's squared units) and its
//                        interval, p, Holm's p, decided, adjacent, the
//                        reference's share of its variance, the repeats of
//                        each, and why an undecided adjacent pair is so
//   verdict_metrics.csv  every verdict metric of every label (corrected
//                        value, interval, raw value): the report's columns
//   verdict_curves.csv   every verdict metric's mean curve over the repeats
//                        against time_s and spp (`x`), at 64 points x_value,
//                        with its interval (the runs' spread): the plots'
//                        lines and bands
// Values are in the metric's own units (RMSE for rmse, relMSE for relmse).
#include <map>
#include <string>
#include <vector>
#include "experiments/verdict/sequential.h"
#include "experiments/verdict/verdict.h"

namespace lb {

struct VerdictInputs {
  std::string runDir;
  VerdictSettings settings;  // its baseline index is per scene: see baseline
  std::string baseline;      // a label; empty: the first
  RepeatPlan plan;
  struct Scene {
    std::string name;
    Crop crop;
    uint64_t referenceChunks = 0;
  };
  std::vector<Scene> scenes;
  std::vector<std::string> labels;       // meta.json's configurations, in order (denoised ones too)
  std::vector<size_t> configurationOf;  // each label's configuration (its runs)
};

// From meta.json; throws std::runtime_error naming the file if it is missing
// or lacks what a verdict needs (a run started before issue 32).
VerdictInputs readVerdictInputs(const std::string& runDir);

// One scene judged: the verdict, the other metrics' estimates per label,
// and the repeats each label was judged with.
struct SceneJudgement {
  std::string scene;
  JudgedScene judged;
  std::vector<std::string> labels;
  std::vector<int> repeats;
  std::map<std::string, std::vector<Estimate>> metrics;  // metric -> per label
  // (label, metric) -> the mean curve over repeats against time and against spp.
  std::map<std::pair<std::string, std::string>, std::pair<MeanCurve, MeanCurve>> curves;
};

// `repeatLimit[c]`: judge configuration c's repeats [0, limit) only (a
// sequential look); empty: every repeat the log has finished.
SceneJudgement judgeRunScene(const VerdictInputs& inputs, size_t scene, const std::vector<int>& repeatLimit = {});

void writeVerdictFiles(const VerdictInputs& inputs, const std::vector<SceneJudgement>& scenes);
// meta.json's "verdict" settings as `inputs` has them (after `lightbench
// verdict` changed them), so that the report states what the files hold.
void recordVerdictSettings(const VerdictInputs& inputs);

// The verdict's one-line-per-scene summary for the terminal: the ranking
// with groups, and the adjacent pairs still undecided.
std::string verdictSummary(const VerdictInputs& inputs, const std::vector<SceneJudgement>& scenes);

}  // namespace lb
