#pragma once
// One run of an experiment: a configuration on a scene, one repeat, rendered
// within the budget, with a log row (run_log.h) at each snapshot and at the
// end. Used alike by a single process (runner.cpp) and by an MPI worker, whose
// rows and final images go back to rank 0 to be written (experiments/
// cluster.h): so a distributed run writes what a single process would.
#include <functional>
#include <optional>
#include <string>
#include <vector>
#include "core/image.h"
#include "core/scene_loader.h"
#include "experiments/experiment.h"

namespace lb {

struct RunTask {
  size_t scene = 0, config = 0;
  int repeat = 0;
};

// Where runs are timed, for the log's host, cpu and threads columns.
struct MachineColumns {
  std::string host, cpu;
  int threads = 1;
};

// What every run of an experiment shares.
struct RunEnvironment {
  const Experiment* experiment = nullptr;
  const std::vector<SceneFile>* scenes = nullptr;
  // Per scene, per configuration: the parameters with the scene's shared
  // keys (an imported scene's max_depth) merged in. Built once, only read.
  std::vector<std::vector<YAML::Node>> params;
  std::vector<double> snapshots;  // seconds or passes (snapshotPoints)
  MachineColumns machine;
};

RunEnvironment makeRunEnvironment(const Experiment& e, const std::vector<SceneFile>& scenes,
                                  const MachineColumns& machine);

// A snapshot as it is logged, for a progress line.
struct RunProgress {
  size_t snapshot = 0, snapshots = 0;  // 1-based; snapshot == snapshots when final
  double seconds = 0, rmse = 0;
  uint64_t passes = 0;
  bool final = false;
};

struct RunOutcome {
  Image image;                    // the final image
  std::optional<Image> denoised;  // filtered too (`denoise:`)
};

// Renders the run. Each row goes to `row` as it is made, a denoised row
// before its raw one, and the final raw row last; `progress` is called after
// each raw row. `referenceVariance` (per pixel, of the reference's mean;
// empty if unknown) corrects the logged squared errors.
RunOutcome performRun(const RunEnvironment& env, const RunTask& task, const Image& reference,
                      const Image& referenceVariance,
                      const std::function<void(std::vector<std::string>&&)>& row,
                      const std::function<void(const RunProgress&)>& progress);

// The run's images in the run folder: repeat 0's EXR, PNG, error and crop
// images (and the denoised ones), another repeat's EXR only.
void writeRunImages(const std::string& runDir, const Experiment& e, const RunTask& task, const RunOutcome& outcome,
                    const Image& reference);

// Repeat 0's image is <stem>.exr (shown in the report), repeat r's <stem>__repeat<r>.exr.
std::string repeatImagePath(const std::string& stem, int repeat);

}  // namespace lb
