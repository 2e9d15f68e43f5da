#pragma once
// Verdicts (issue 32): which configuration wins on a scene, with what
// confidence. For one scene and one squared-error metric (metrics.h) this
// gives every configuration's final error corrected for the reference's
// noise with a confidence interval, every pair's test, rank groups, and
// efficiency, speed-up over a baseline and time to reach the baseline's
// error, each with its interval. docs/testing.md ("Verdicts") states and
// justifies each choice; in short:
//
// * A configuration's value is the mean over its repeats of the corrected
//   metric. With two repeats or more its variance is the repeats' sample
//   variance / R (R − 1 degrees of freedom) plus the reference's part, which
//   the repeats cannot see because every repeat is compared with the same
//   reference: per value (pixel and channel) of weight w, reference variance
//   v (estimated from c chunks) and bias b of the configuration,
//       Var = Σ w² (2 v² (1 + 1/(c − 1)) + 4 b² v) / N²
//   (the correction's own error and the bias's cross term with the
//   reference's error, for normal reference errors; each estimated without
//   bias per value, summed, then clamped at 0; a pixel's three channels
//   counted 3× for their unknown correlation), with Satterthwaite's degrees
//   of freedom over the pixels, each with c − 1. With
//   one repeat, the variance comes from batch means over tiles of the image
//   (the tiles' errors independent: statistics.h), which hold the
//   reference's noise too. Intervals: Student t with Welch–Satterthwaite
//   degrees of freedom.
// * A pair's difference is tested on the untransformed values (the
//   correction is a constant shared by every configuration, so raw and
//   corrected values give the same test): Welch's t, its variance the two
//   repeats' variances plus the reference's part of the difference,
//   4 Σ w² (b_A − b_B)² v / N², which vanishes for two unbiased methods. Two
//   single repeats are compared tile by tile (paired batch means): the
//   correction's error cancels in each tile's difference, and the rest of
//   the reference's noise (−2 ε (x_A − x_B) per value) varies from tile to
//   tile, so the tiles' spread holds it. Holm's correction over all pairs of the
//   scene keeps the family-wise error at 1 − confidence (divided among the
//   looks of a sequential experiment).
// * Rank groups: configuration i's rank lies in [1 + #(significantly
//   better), K − #(significantly worse)], a statement that holds for every
//   configuration at once with the family-wise confidence. A configuration is
//   decided when that interval is one rank.
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>
#include "core/image.h"
#include "experiments/metrics.h"

namespace lb {

// The metrics a verdict can rank by: rmse, relmse, relmse_trimmed,
// rmse_crop, relmse_crop (MAPE has no correction for the reference).
struct VerdictMetric {
  std::string name;
  SquaredError kind = SquaredError::Mse;
  bool crop = false;
  std::string correctedColumn;  // log.csv's column of its corrected value
};
const std::vector<VerdictMetric>& verdictMetrics();
std::optional<VerdictMetric> findVerdictMetric(const std::string& name);
// A squared-domain value as the metric is named: √ for the RMSE metrics
// (negative corrected MSEs shown as 0), the value itself otherwise.
double displayValue(const std::string& metric, double squared);

struct ConfigurationEvidence {
  std::string label;
  std::vector<Image> finals;    // each repeat's final image
  std::vector<double> seconds;  // each repeat's final time
  // Each repeat's snapshots of the ranked metric: (time, corrected value).
  std::vector<std::vector<std::pair<double, double>>> curves;
};

struct SceneEvidence {
  Image reference, referenceVariance;  // the variance of the mean per pixel; empty: unknown
  uint64_t referenceChunks = 0;        // the chunks it was estimated from (dof: chunks − 1)
  Crop crop;
  std::vector<ConfigurationEvidence> configurations;
};

struct VerdictSettings {
  std::string rankBy = "relmse";
  double confidence = 0.95;
  // Sequential experiments share 1 − confidence among their looks
  // (Bonferroni): every interval and test of the run uses alpha().
  int looks = 1;
  size_t baseline = 0;
  MetricSettings metric;
  int tileSize = 8;
  double alpha() const { return (1 - confidence) / looks; }
};

// A metric's estimate, in the squared domain (MSE, relMSE).
struct Estimate {
  double value = 0, raw = 0;     // corrected and raw means over the repeats
  double variance = 0;           // of `value`: the runs' part plus the reference's
  double runsVariance = 0;       // the runs' part (repeats, or tiles)
  double referenceVariance = 0;  // the reference's part
  double dof = INFINITY;
  double low = 0, high = 0;      // its interval at the verdict's level
  int repeats = 0;
};

struct PairComparison {
  size_t a = 0, b = 0;  // configurations; a is ranked before b (value_a ≤ value_b)
  double difference = 0, low = 0, high = 0;  // value_a − value_b and its interval
  double p = 1, pAdjusted = 1, dof = 0;
  double referenceShare = 0;  // of the difference's variance
  bool decided = false, adjacent = false;
};

struct ConfigurationVerdict {
  Estimate estimate;
  int rankLow = 1, rankHigh = 1;
  bool decided = false;
  double seconds = 0;  // mean final time
  // 1 / (value · seconds); with the interval the value's interval gives
  // (time taken as known: at equal time it varies little).
  double efficiency = 0, efficiencyLow = 0, efficiencyHigh = 0;
  // Efficiency over the baseline's; its interval from both values'
  // intervals at half the level each (Bonferroni): conservative.
  double speedup = 1, speedupLow = 1, speedupHigh = 1;
  // When the mean curve first reaches the baseline's final value, and when
  // its interval's lower and upper edges do (NaN: not within the budget).
  double timeToTarget = NAN, timeToTargetLow = NAN, timeToTargetHigh = NAN;
  std::string rankGroup() const;  // "2" or "2-3"
};

struct SceneVerdict {
  std::string metric;
  std::vector<ConfigurationVerdict> configurations;  // in the evidence's order
  std::vector<size_t> order;                         // best first
  std::vector<PairComparison> pairs;                 // every pair, adjacent ones marked
  double target = NAN;                               // the baseline's value
  bool referenceVarianceKnown = false;
};

SceneVerdict judgeScene(const SceneEvidence& evidence, const VerdictSettings& settings);

// The mean over repeats of curves of (x, value) pairs (each sorted by x), on
// `points` log-spaced x over the range every curve covers (between its
// samples: log–log where the values are positive, else linear in log x),
// with the interval of the mean at level 1 − alpha (Student t over the
// repeats; none with one repeat). The report's bands and time to target.
struct MeanCurve {
  std::vector<double> x, mean, low, high;
};
MeanCurve meanCurve(const std::vector<std::vector<std::pair<double, double>>>& curves, double alpha, int points = 64);
// One configuration's estimate of any verdict metric (the report's other columns).
Estimate estimateMetric(const SceneEvidence& evidence, size_t configuration, const std::string& metric,
                        const VerdictSettings& settings);

}  // namespace lb
