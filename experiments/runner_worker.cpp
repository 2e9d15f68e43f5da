// A farm worker's side of an experiment (`lightbench run` under mpirun, ranks
// other than 0): it renders the reference chunks and runs rank 0 sends it.
#include "experiments/runner.h"
#include "experiments/runner_parts.h"
#include "experiments/report_step.h"
#include <tbb/info.h>
#include <algorithm>
#include <tbb/task_arena.h>
#include <unistd.h>
#include <atomic>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <thread>
#include "core/scene_loader.h"
#include "experiments/decomposition.h"
#include "experiments/meta.h"
#include "experiments/reference.h"
#include "experiments/run_lock.h"
#include "experiments/run_log.h"
#include "experiments/run_one.h"
#include "experiments/validate.h"
#include "experiments/verdict/run_folder.h"
#include "integrators/registry.h"

namespace lb {

using namespace runner;

int serveExperiment(const std::string& experimentFile, const ExperimentOptions& eo, const RunnerOptions& o) {
  Farm& farm = *o.farm;
  // Loaded at the first task, which rank 0 sends only once its own checks
  // passed: a bad input is reported once, by rank 0.
  std::optional<Experiment> e;
  std::optional<CheckedExperiment> checked;
  std::optional<RunEnvironment> env;
  std::map<size_t, SceneFile> referenceScenes;
  std::map<size_t, Image> references, referenceVariances;
  const int threads = workerThreads(o.threads, farm.cluster());
  std::string identity;  // jobIdentity, as this rank reads the files
  const std::string me = "[rank " + std::to_string(farm.cluster().rank()) + "] ";
  enableFlushToZeroOnAllThreads();
  tbb::task_arena arena(threads);
  return farm.serve([&](const std::string& bytes) {
    if (!e) {
      // mpirun binds each rank to one core by default when there are at most
      // 2 ranks: the rank then renders with the cores it may use, and says so
      // at its first task, which comes only once rank 0 accepted the input (a
      // refused one gets rank 0's one error line, and nothing after it).
      int share = int(std::thread::hardware_concurrency()) / std::max(1, farm.cluster().workersOnThisNode());
      if (threads < share)
        std::fprintf(stderr, "%snote: may use %d of this node's %u cores (mpirun's binding), so its runs get %d thread(s); "
                     "mpirun --bind-to none gives each of the node's %d worker rank(s) %d\n", me.c_str(), threads,
                     std::thread::hardware_concurrency(), threads, farm.cluster().workersOnThisNode(), share);
      e = loadExperiment(experimentFile, eo);
      checked = validateExperiment(*e);
      env = makeRunEnvironment(*e, checked->scenes, thisMachine(threads));
      identity = jobIdentity(*e, experimentHashOf(*e, referenceIdsOf(*e)));
    }
    ByteReader r(bytes);
    if (r.str() != identity)
      throw ConfigError(experimentFile, 0, "", "this rank (" + hostName() + ") reads another experiment, other scene "
                        "files or runs another lightbench build than rank 0; every rank must see the same files "
                        "(a shared file system) and run the same build");
    uint64_t kind = r.u64();
    size_t si = r.u64();
    const ExperimentScene& es = e->scenes.at(si);
    std::string result;
    if (kind == ReferenceChunkTask) {
      uint64_t k = r.u64();
      if (!referenceScenes.count(si)) referenceScenes.emplace(si, loadReferenceScene(es));
      arena.execute([&] { result = chunkResult(k, renderReferenceChunk(es, referenceScenes.at(si), k)); });
      return result;
    }
    RunTask t;
    t.scene = si;
    t.config = r.u64();
    t.repeat = int(r.u64());
    if (r.u64()) references[si] = r.image(), referenceVariances[si] = r.image();
    const Configuration& c = e->configurations.at(t.config);
    std::vector<std::vector<std::string>> rows;
    arena.execute([&] {
      RunOutcome outcome = performRun(
          *env, t, references.at(si), referenceVariances.at(si), [&](std::vector<std::string>&& row) { rows.push_back(std::move(row)); },
          [&](const RunProgress& p) {
            std::fprintf(stderr, "%s%s / %-22s repeat %d  snapshot %zu/%zu  t=%.2fs spp=%llu RMSE=%.4g%s\n",
                         me.c_str(), es.name.c_str(), ("'" + c.label + "'").c_str(), t.repeat + 1, p.snapshot,
                         p.snapshots, p.seconds, (unsigned long long)p.passes, p.rmse, p.final ? " final" : "");
          });
      result = encodeRunResult(rows, outcome);
    });
    return result;
  });
}

}  // namespace lb
