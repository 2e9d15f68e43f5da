// The runner's shared parts (runner_parts.h): identities, the result a
// worker sends, the decomposition file.
#include "experiments/runner_parts.h"
#include "experiments/runner.h"
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

namespace fs = std::filesystem;

namespace lb::runner {

// decomposition.csv: each configuration's final MSE split into bias² and
// variance over its repeats, with 95 % intervals (experiments/decomposition.h).
// Read back from the run folder, so a resumed run includes the earlier runs;
// the repeats [0, targets[scene][configuration]) of a sequential run.
void writeDecomposition(const Experiment& e, const std::filesystem::path& runDir, const std::vector<Reference>& references,
                        const RepeatTargets& targets) {
  std::ostringstream csv;
  csv << "scene,label,integrator,repeats,mse,bias2,bias2_low,bias2_high,variance,variance_low,variance_high,"
         "reference_variance\n";
  for (size_t si = 0; si < e.scenes.size(); ++si)
    for (size_t ci = 0; ci < e.configurations.size(); ++ci) {
      const Configuration& c = e.configurations[ci];
      std::string stem = (runDir / (e.scenes[si].name + "__" + slug(c.label))).string();
      // The repeats whose images are there: a run resumed from a folder that
      // a version without them started has fewer. Never fails the run.
      std::vector<Image> finals;
      for (int r = 0; r < targets[si][ci]; ++r)
        if (fs::exists(repeatImagePath(stem, r))) finals.push_back(readExr(repeatImagePath(stem, r)));
      if (finals.size() < 2) {
        std::cerr << "warning: " << e.scenes[si].name << " / " << c.label << ": " << finals.size()
                  << " final image(s) of its repeats in the run folder; no bias²/variance split\n";
        continue;
      }
      ErrorDecomposition d = decomposeError(finals, references[si].image, references[si].variance);
      csv << csvField(e.scenes[si].name) << "," << csvField(c.label) << "," << c.integrator << "," << d.repeats;
      // An unknown reference variance (a given EXR) is an empty field: bias²
      // then includes it (the report says so).
      for (double v : {d.mse, d.bias2, d.bias2Low, d.bias2High, d.variance, d.varianceLow, d.varianceHigh,
                       d.referenceVariance})
        csv << "," << (std::isfinite(v) ? logNumber(v) : "");
      csv << "\n";
    }
  writeTextFile((runDir / "decomposition.csv").string(), csv.str());
}

// Threads per run: --threads, else the cores this process may use shared
// among the runs at once (--jobs) or the workers on this node.
int threadsPerRun(const RunnerOptions& o, int sharers) {
  if (o.threads > 0) return o.threads;
  return std::max(1, tbb::info::default_concurrency() / std::max(1, sharers));
}

// What a resumed run must share with the one it continues: the experiment as
// read, its budget and repeats, and its references' keys.
std::string experimentHashOf(const Experiment& e, const std::vector<std::string>& referenceIds) {
  std::vector<std::string> parts = {YAML::Dump(e.source), std::to_string(e.budget.seconds),
                                    std::to_string(e.budget.spp), std::to_string(e.repeats)};
  parts.insert(parts.end(), referenceIds.begin(), referenceIds.end());
  return hashStrings(parts);
}

// What every rank must share to work on one experiment: that, the run
// scenes' bytes and the build (the references' keys already hash their
// scenes, meshes and the rendering code). A worker that reads another copy
// (a stale file on a node, another build) refuses its tasks.
std::string jobIdentity(const Experiment& e, const std::string& experimentHash) {
  std::vector<std::string> parts = {experimentHash, renderSourceHash(), LIGHTBENCH_GIT};
  for (const auto& s : e.scenes) parts.push_back(fileBytes(s.path));
  return hashStrings(parts);
}

std::vector<std::string> referenceIdsOf(const Experiment& e) {
  std::vector<std::string> ids;
  for (const auto& s : e.scenes)
    ids.push_back(s.reference.file.empty() ? referenceKey(s) : s.reference.file + "|" + s.reference.varianceFile);
  return ids;
}

MachineColumns thisMachine(int threads) { return {hostName(), cpuModel(), threads}; }

std::string encodeRunResult(const std::vector<std::vector<std::string>>& rows, const RunOutcome& out) {
  ByteWriter w;
  w.u64(rows.size());
  for (const auto& r : rows) {
    w.u64(r.size());
    for (const auto& f : r) w.str(f);
  }
  w.image(out.image).u64(out.denoised ? 1 : 0);
  if (out.denoised) w.image(*out.denoised);
  return w.take();
}

void decodeRunResult(const std::string& bytes, std::vector<std::vector<std::string>>& rows, RunOutcome& out) {
  ByteReader r(bytes);
  rows.resize(r.u64());
  for (auto& row : rows) {
    row.resize(r.u64());
    for (auto& f : row) f = r.str();
  }
  out.image = r.image();
  if (r.u64()) out.denoised = r.image();
}

}  // namespace lb::runner
