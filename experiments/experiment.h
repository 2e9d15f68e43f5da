#pragma once
// An experiment file (experiments/*.yaml): scenes with references, integrator
// configurations, a budget, snapshots, metrics and repeats. Parsed with the
// same file:line:key errors as scenes; integrator names and parameters are
// checked before anything renders.
#include <optional>
#include <string>
#include <vector>
#include "core/params.h"
#include "experiments/metrics.h"
#include "experiments/verdict/sequential.h"
#include "integrators/render_loop.h"

namespace lb {

// The longest time budget anything may ask for: an experiment's or a
// reference's seconds, `render --time`. A typo of 1e30 ran forever (issue 34).
inline constexpr double kMaxBudgetSeconds = 30 * 24 * 3600.0;

// Where a key was written, for checks that need more than the experiment file
// (a reference's size needs the scene loaded): their errors name it too.
struct KeyLocation {
  std::string file, key;
  int line = 0;
  ConfigError error(const std::string& message) const { return ConfigError(file, line, key, message); }
};

struct ReferenceSpec {
  std::string file;            // an EXR to use as is, or empty: compute and cache
  // With `file`: its per-pixel variance of the mean (an EXR, e.g. a cached
  // reference's NAME-KEY.variance.exr) and the number of independent chunks
  // that variance was estimated from (0: unknown), so that errors against a
  // given reference are corrected for its noise too.
  std::string varianceFile;
  uint64_t chunks = 0;
  std::string scene;           // render it from this scene instead of the run's (e.g. the unscaled or the
                               // point-light version); empty: the run's scene with all its overrides
  std::string integrator = "path";
  YAML::Node params{YAML::NodeType::Map};
  // The budget: one of spp, seconds or a target noise floor (RMSE of the
  // reference's own noise). It is rendered in chunks of chunkSpp samples per
  // pixel with independent seeds, averaged; the cache keeps the chunks' mean
  // and variance, so a larger budget later extends it instead of starting over.
  uint64_t spp = 1024;         // 0 when seconds or noiseFloor is the budget
  double seconds = 0;
  double noiseFloor = 0;
  uint64_t chunkSpp = 256;
  uint64_t seed = 1000003;     // distinct from the runs' seeds
};

struct ExperimentScene {
  std::string path;            // resolved against the experiment file's folder
  std::string name;            // `name`, or the file stem: used in file names and the CSV; unique
  YAML::Node overrides{YAML::NodeType::Map};  // film resolution, world_scale
  YAML::Node resolution{YAML::NodeType::Map}; // the film override alone (given to a reference scene)
  ReferenceSpec reference;
  Crop crop;
  // The keys validateExperiment() reports against: `scene`, `reference`
  // (its `file` or `scene` when given) and `crop`.
  KeyLocation sceneAt, referenceAt, cropAt;
};

struct Configuration {
  std::string label, integrator;
  YAML::Node params{YAML::NodeType::Map};
  std::string context;         // "configurations[i].params": errors found while rendering name the key as written
  // A member of a `sweep:` (one combination of its values): the configuration's
  // own label, which groups the members in the plots, and the swept values.
  std::string sweepGroup;
  YAML::Node sweepValues{YAML::NodeType::Map};
  // `sampler:` in the configuration replaces the scenes' own (core/sampler.h).
  std::optional<SamplerSettings> sampler;
  // `denoise: nlmeans`: every snapshot is also filtered (core/denoise.h) and
  // logged as its own configuration, denoisedLabel(), at the time the render
  // took plus the features' and the filter's (so the plots show both trades).
  std::string denoise;
  KeyLocation denoiseAt;
  // `adaptive: {passes, target_relative_error}` (integrators/adaptive_sampling.h).
  AdaptiveSettings adaptive;
  std::string denoisedLabel() const { return label + " + " + denoise; }
};

enum class SnapshotSpacing { Log, Linear };

struct Experiment {
  std::string name, file;
  std::vector<ExperimentScene> scenes;
  std::vector<Configuration> configurations;
  RenderBudget budget;
  int snapshots = 8;
  SnapshotSpacing spacing = SnapshotSpacing::Log;
  std::vector<std::string> metrics = {"rmse", "relmse", "relmse_trimmed", "mape", "variance"};
  // The most repeats a configuration gets: `repeats: N`, or the schedule's
  // max with `repeats: {until_decided: true, ...}` (verdict/sequential.h).
  int repeats = 1;
  RepeatPlan repeatPlan;
  uint64_t seed = 1;
  MetricSettings metricSettings;
  // The verdict (verdict/verdict.h): the metric it ranks by, the
  // configuration speed-ups are relative to (a label; empty: the first),
  // and the confidence of its intervals and family-wise tests.
  std::string rankBy = "relmse";
  std::string baseline;
  double confidence = 0.95;
  YAML::Node source;           // the file as read, for meta.json
};

struct ExperimentOptions {
  bool quick = false;          // budget ÷ 4, one repeat, reference budget ÷ 4 (its floor × 2); unbuilt integrators skipped
};

Experiment loadExperiment(const std::string& path, const ExperimentOptions& options);

// A configuration label as it appears in file names: letters and digits, lower
// case, everything else '-'. Labels must differ in this form.
std::string slug(const std::string& label);
// A YAML node in flow style, so block and flow spellings of a mapping agree.
std::string flowYaml(const YAML::Node& node);

}  // namespace lb
