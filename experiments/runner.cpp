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

namespace fs = std::filesystem;

namespace lb {

using namespace runner;

namespace {

std::string formatDuration(double s) {
  char buf[32];
  if (s < 60) std::snprintf(buf, sizeof buf, "%.0fs", s);
  else std::snprintf(buf, sizeof buf, "%dm%02ds", int(s) / 60, int(s) % 60);
  return buf;
}

// The latest run of the experiment, for --resume; empty: start a new one.
fs::path latestRun(const Experiment& e, const RunnerOptions& o) {
  fs::path base = fs::path(o.resultsRoot) / e.name;
  if (!o.resume) return {};
  if (fs::exists(base)) {
    std::vector<fs::path> runs;
    for (const auto& d : fs::directory_iterator(base))
      if (d.is_directory() && fs::exists(d.path() / "log.csv")) runs.push_back(d.path());
    if (!runs.empty()) return *std::max_element(runs.begin(), runs.end());
  }
  std::cerr << "resume: no earlier run of '" << e.name << "'; starting a new one\n";
  return {};
}

// A new run folder, created here: create_directory fails on an existing one,
// so two runs started in the same second never share a folder.
fs::path createRunDir(const Experiment& e, const RunnerOptions& o) {
  fs::path base = fs::path(o.resultsRoot) / e.name;
  fs::create_directories(base);
  std::time_t now = std::time(nullptr);
  char id[32];
  std::strftime(id, sizeof id, "%Y%m%d-%H%M%S", std::gmtime(&now));
  fs::path dir = base / id;
  for (int i = 2; !fs::create_directory(dir); ++i) dir = base / (std::string(id) + "-" + std::to_string(i));
  return dir;
}



// A run's rows as the log gets them: the snapshots in order, then its raw
// final row, which marks the run finished for --resume, then the denoised
// final row. One write: a kill can tear only the last, and then the denoised
// label misses that repeat rather than having it twice when the run is redone.
std::vector<std::vector<std::string>> inLogOrder(std::vector<std::vector<std::string>> rows, const std::string& label) {
  auto rank = [&](const std::vector<std::string>& r) { return r.back() != "1" ? 0 : r[1] == label ? 1 : 2; };
  std::stable_sort(rows.begin(), rows.end(), [&](const auto& a, const auto& b) { return rank(a) < rank(b); });
  return rows;
}


}  // namespace

std::string runExperiment(const Experiment& e, const RunnerOptions& o) {
  using Clock = std::chrono::steady_clock;
  Farm* farm = o.farm && o.farm->workers() > 0 ? o.farm : nullptr;
  // Every input first: a bad one fails in seconds, before any reference
  // renders, and leaves no run folder behind.
  CheckedExperiment checked = validateExperiment(e);

  // Each reference's key hashes its scene and mesh files: computed once here.
  std::vector<std::string> referenceIds = referenceIdsOf(e);
  std::string experimentHash = experimentHashOf(e, referenceIds);
  const std::string job = farm ? jobIdentity(e, experimentHash) : "";
  fs::path runDir = latestRun(e, o);
  std::optional<RunLock> lock;
  if (!runDir.empty()) {
    if (fs::exists(runDir / "meta.json")) {
      // A meta.json that is not one the runner wrote (truncated, edited) is
      // named as such, not taken for a changed experiment.
      if (readExperimentHash(runDir.string()).empty())
        throw ConfigError((runDir / "meta.json").string(), 0, "experiment_hash",
                          "not a run's metadata (unreadable JSON or no experiment_hash): this run folder cannot be "
                          "resumed; run without --resume to start a new run");
      if (readExperimentHash(runDir.string()) != experimentHash)
        throw ConfigError(e.file, 0, "--resume",
                          "the experiment, its budget or its references changed since " + runDir.string() +
                              " was started; run without --resume to start a new run");
    }
    // Before anything is rendered or rewritten: one writer per run folder,
    // and a log that is one (a corrupt log.csv is refused, not restarted).
    lock.emplace(runDir.string(), e.file);
    std::set<std::string> finished;
    readResumableLog((runDir / "log.csv").string(), &finished);
  }

  // References (rendered with every core, or by every worker) before the run
  // folder exists: a reference that fails leaves no half-started run.
  std::vector<Reference> references(e.scenes.size());
  auto obtain = [&](size_t si, const ExperimentScene& s) {
    if (!s.reference.file.empty()) {
      std::cerr << "reference: " << s.reference.file << " (given"
                << (s.reference.varianceFile.empty() ? "" : ", with its variance " + s.reference.varianceFile) << ")\n";
      Reference given;
      given.image = checked.givenReferences[si];
      given.variance = checked.givenVariances[si];
      given.chunks = s.reference.chunks;
      if (!given.variance.pixels.empty()) {
        double sum = 0;
        for (const Color& c : given.variance.pixels) sum += double(c.r) + c.g + c.b;
        given.varianceOfMean = sum / (3.0 * double(given.variance.pixels.size()));
      }
      given.description = "file " + s.reference.file +
                          (s.reference.varianceFile.empty() ? "" : ", variance " + s.reference.varianceFile);
      return given;
    }
    if (farm) {
      RemoteChunks remote{*farm, [si, &job](uint64_t k) {
                            return ByteWriter().str(job).u64(ReferenceChunkTask).u64(si).u64(k).take();
                          }};
      return obtainReference(s, o.resultsRoot, referenceIds[si], &remote);
    }
    return obtainReference(s, o.resultsRoot, referenceIds[si]);
  };
  for (size_t si = 0; si < e.scenes.size(); ++si) {
    const ExperimentScene& s = e.scenes[si];
    references[si] = obtain(si, s);
    const Camera& camera = checked.scenes[si].scene->camera;
    // A given EXR of another size is refused before this; a safety net.
    if (references[si].image.width != camera.width() || references[si].image.height != camera.height())
      throw s.referenceAt.error("reference of " + s.name + " is " + std::to_string(references[si].image.width) + "×" +
                                std::to_string(references[si].image.height) + ", the scene renders " +
                                std::to_string(camera.width()) + "×" + std::to_string(camera.height()));
  }

  std::atomic<size_t> done{0};  // runs finished by this process
  // A new run that fails (an exception, e.g. a photon map too large for
  // memory) before any of its runs finished leaves no folder behind: it holds
  // no result, and --resume would redo an unfinished run anyway.
  struct DiscardUnlessKept {
    fs::path dir;
    const std::atomic<size_t>& done;
    bool keep = false;
    ~DiscardUnlessKept() {
      std::error_code ec;
      if (!keep && !dir.empty() && done == 0) fs::remove_all(dir, ec), fs::remove(dir.parent_path(), ec);
    }
  } discard{{}, done};
  if (runDir.empty()) {
    runDir = createRunDir(e, o);
    lock.emplace(runDir.string(), e.file);
    discard.dir = runDir;
  }
  std::cerr << "experiment '" << e.name << "': " << runDir.string() << (o.resume ? " (resuming)" : "")
            << (farm ? " on " + std::to_string(farm->workers()) + " MPI worker rank(s)" : "") << "\n";

  std::set<std::string> completed;
  LogWriter log((runDir / "log.csv").string(), o.resume, &completed);
  std::mutex completedMutex;

  int jobs = farm ? 1 : std::max(1, std::min(o.jobs, tbb::info::default_concurrency()));
  // Under MPI: what a worker on rank 0's node uses (each row has its own).
  int threads = farm ? workerThreads(o.threads, farm->cluster()) : threadsPerRun(o, jobs);
  RunMeta meta = startMeta(e, runDir.string(), threads, jobs, experimentHash);
  meta.ranks = farm ? farm->cluster().size() : 1;
  // The reference beside the run's images, with its variance: the folder is
  // complete for the verdict, lightbench.load_run and the report's viewer.
  auto recordReference = [&](size_t si) {
    const ExperimentScene& s = e.scenes[si];
    const Reference& r = references[si];
    meta.referenceRmseFloor[s.name] = std::sqrt(r.varianceOfMean);
    meta.referenceKeys[s.name] = referenceIds[si];
    meta.referenceUsed[s.name] = r.description.empty() ? "file " + s.reference.file : r.description;
    meta.referenceChunks[s.name] = r.chunks;
    writeExr((runDir / (s.name + "__reference.exr")).string(), r.image);
    fs::path variance = runDir / (s.name + "__reference_variance.exr");
    if (!r.variance.pixels.empty()) writeExr(variance.string(), r.variance);
    else fs::remove(variance);
    writePng((runDir / (s.name + "__reference.png")).string(), r.image);
    if (!s.crop.empty())
      writePng((runDir / (s.name + "__reference_crop.png")).string(), cropImage(r.image, s.crop, 4));
  };
  for (size_t si = 0; si < e.scenes.size(); ++si) recordReference(si);
  writeMeta(meta, e, runDir.string(), false);

  const bool timeBudget = e.budget.seconds > 0;
  auto experimentStart = Clock::now();
  std::mutex progressMutex;
  RunEnvironment env = makeRunEnvironment(e, checked.scenes, thisMachine(threads));
  std::set<std::pair<int, size_t>> sentReference;  // (worker, scene): a worker has the reference
  double handlingSeconds = 0;                       // rank 0's own work per run under MPI

  // Renders the runs not yet finished among `tasks`: here (`jobs` at a
  // time) or on the farm's workers.
  auto renderTasks = [&](const std::vector<RunTask>& tasks) {
    done = 0;
    auto elapsedText = [&](double runSeconds, bool final) {
      double elapsed = std::chrono::duration<double>(Clock::now() - experimentStart).count();
      // Per run: the time budget, or (sample budgets) the mean of finished runs.
      double perRun = timeBudget ? e.budget.seconds : (done > 0 ? elapsed / double(done) : 0);
      int parallel = farm ? farm->workers() : jobs;
      double eta = perRun > 0 ? perRun * double(tasks.size() - done) / parallel - (final ? 0 : runSeconds) : 0;
      return "(elapsed " + formatDuration(elapsed) + (eta > 0 ? ", ETA " + formatDuration(eta) : "") + ")";
    };
    auto finished = [&](const RunTask& t) {
      std::lock_guard<std::mutex> guard(completedMutex);
      completed.insert(runKey(e.scenes[t.scene].name, e.configurations[t.config].label, std::to_string(t.repeat)));
    };
    if (farm) {
      // Runs go to whichever worker asks; each comes back whole (its rows and
      // final images), and is written here: the images first, the rows last,
      // as a single process does. A worker is sent a scene's reference with
      // its first run of that scene.
      size_t next = 0;
      std::map<int, RunTask> running;
      farm->distribute(
          [&](int worker) -> std::optional<std::string> {
            if (next >= tasks.size()) return std::nullopt;
            const RunTask& t = tasks[next++];
            running[worker] = t;
            ByteWriter w;
            w.str(job).u64(RunTaskKind).u64(t.scene).u64(t.config).u64(uint64_t(t.repeat));
            bool send = sentReference.insert({worker, t.scene}).second;
            w.u64(send ? 1 : 0);
            if (send) w.image(references[t.scene].image).image(references[t.scene].variance);
            return w.take();
          },
          [&](int worker, std::string&& bytes) {
            auto handleStart = Clock::now();
            RunTask t = running.at(worker);
            std::vector<std::vector<std::string>> rows;
            RunOutcome outcome;
            decodeRunResult(bytes, rows, outcome);
            writeRunImages(runDir.string(), e, t, outcome, references[t.scene].image);
            log.write(inLogOrder(rows, e.configurations[t.config].label));
            finished(t);
            ++done;
            const std::vector<std::string>& last = rows.back();
            std::fprintf(stderr, "[run %zu/%zu] %s / %-22s repeat %d  done on %s (rank %d, threads %s): t=%ss spp=%s RMSE=%s  %s\n",
                         done.load(), tasks.size(), e.scenes[t.scene].name.c_str(),
                         ("'" + e.configurations[t.config].label + "'").c_str(), t.repeat + 1, last[17].c_str(), worker,
                         last[19].c_str(), last[5].c_str(), last[7].c_str(), last[8].c_str(),
                         elapsedText(0, true).c_str());
            handlingSeconds += std::chrono::duration<double>(Clock::now() - handleStart).count();
          });
      return;
    }
    std::atomic<size_t> next{0};
    auto runOne = [&](const RunTask& t) {
      const ExperimentScene& es = e.scenes[t.scene];
      const Configuration& c = e.configurations[t.config];
      // Rows are logged as they come, but the final ones only after the
      // images: a run counts as finished (for --resume) only once everything
      // it produces is on disk.
      std::vector<std::vector<std::string>> finalRows;
      RunOutcome outcome = performRun(
          env, t, references[t.scene].image, references[t.scene].variance,
          [&](std::vector<std::string>&& row) {
            if (row.back() == "1") finalRows.push_back(std::move(row));
            else log.write(row);
          },
          [&](const RunProgress& p) {
            std::lock_guard<std::mutex> guard(progressMutex);
            std::string over = timeBudget && p.seconds > e.budget.seconds
                                   ? " OVER BUDGET by " + logNumber(p.seconds - e.budget.seconds) + "s"
                                   : "";
            std::fprintf(stderr, "[run %zu/%zu] %s / %-22s repeat %d  snapshot %zu/%zu  t=%.2fs spp=%llu RMSE=%.4g%s%s  %s\n",
                         done.load() + 1, tasks.size(), es.name.c_str(), ("'" + c.label + "'").c_str(), t.repeat + 1,
                         p.snapshot, p.snapshots, p.seconds, (unsigned long long)p.passes, p.rmse,
                         p.final ? " final" : "", over.c_str(), elapsedText(p.seconds, p.final).c_str());
          });
      writeRunImages(runDir.string(), e, t, outcome, references[t.scene].image);
      log.write(inLogOrder(std::move(finalRows), c.label));
      finished(t);
      ++done;
    };

    std::exception_ptr failure;
    std::mutex failureMutex;
    auto worker = [&] {
      // A task arena takes the floating-point mode of the thread that creates
      // it: set flush-to-zero first, so every run traces in the same mode.
      enableFlushToZeroOnAllThreads();
      tbb::task_arena arena(threads);
      try {
        for (size_t i; (i = next++) < tasks.size();) arena.execute([&] { runOne(tasks[i]); });
      } catch (...) {
        std::lock_guard<std::mutex> guard(failureMutex);
        if (!failure) failure = std::current_exception();
        next = tasks.size();  // the other workers stop after their current run
      }
    };
    if (jobs == 1) worker();
    else {
      std::vector<std::thread> pool;
      for (int j = 0; j < jobs; ++j) pool.emplace_back(worker);
      for (auto& th : pool) th.join();
    }
    if (failure) std::rethrow_exception(failure);
  };

  // The looks (verdict/sequential.h): one, with every repeat, unless the
  // experiment runs until decided. Each look renders what its targets add.
  bool firstLook = true;
  size_t finishedBefore = 0;
  auto render = [&](const RepeatTargets& targets) {
    std::vector<RunTask> tasks;
    size_t wanted = 0;
    // Repeat by repeat, the configurations in turn: a shared machine's speed
    // drifts over minutes (two runs of one build minutes apart differed by
    // 11 % in samples per second, docs/results.md), and configuration after
    // configuration would hand that drift to one of them at equal time.
    for (size_t si = 0; si < e.scenes.size(); ++si) {
      int most = 0;
      for (size_t ci = 0; ci < e.configurations.size(); ++ci) most = std::max(most, targets[si][ci]);
      for (int r = 0; r < most; ++r)
        for (size_t ci = 0; ci < e.configurations.size(); ++ci) {
          if (r >= targets[si][ci]) continue;
          ++wanted;
          if (!completed.count(runKey(e.scenes[si].name, e.configurations[ci].label, std::to_string(r))))
            tasks.push_back({si, ci, r});
        }
    }
    if (firstLook && tasks.size() < wanted)
      std::cerr << "resume: " << wanted - tasks.size() << " of " << wanted << " runs already complete\n";
    if (!firstLook && !tasks.empty())
      std::cerr << "until decided: " << tasks.size() << " more run(s) for the configurations still undecided\n";
    firstLook = false;
    renderTasks(tasks);
    finishedBefore += done;
    if (finishedBefore > 0) discard.keep = true;
  };
  auto judge = [&](size_t si, const std::vector<int>& repeats) {
    return judgeRunScene(readVerdictInputs(runDir.string()), si, repeats).judged;
  };
  auto extendReference = [&](size_t si) {
    // Twice its chunks, as a sample budget: the cache (keyed without the
    // budget) is extended, not replaced.
    ExperimentScene s = e.scenes[si];
    const Reference& r = references[si];
    s.reference.spp = 2 * std::max<uint64_t>(r.chunks, 1) * r.chunkSpp;
    s.reference.seconds = 0, s.reference.noiseFloor = 0;
    std::cerr << "until decided: " << s.name << ": the reference's noise keeps a pair undecided; extending it to "
              << s.reference.spp << " spp\n";
    references[si] = obtain(si, s);
    recordReference(si);
    writeMeta(meta, e, runDir.string(), false);
    for (auto it = sentReference.begin(); it != sentReference.end();)
      it = it->second == si ? sentReference.erase(it) : std::next(it);
  };
  RepeatTargets targets = runLooks(e.repeatPlan, e.scenes.size(), e.configurations.size(), render, judge,
                                   extendReference);
  discard.keep = true;
  // From here to the report is rank 0's alone, whatever the number of ranks
  // (the README's MPI overhead figures).
  auto lastRunEnd = Clock::now();
  if (farm && finishedBefore > 0)
    std::fprintf(stderr, "rank 0: %.3f s for %zu runs' results (%.1f ms each: decoding, writing images and rows)\n",
                 handlingSeconds, finishedBefore, 1000 * handlingSeconds / double(finishedBefore));

  if (e.repeats > 1) writeDecomposition(e, runDir, references, targets);
  // The verdict (verdict/run_folder.h) from the run folder as written.
  {
    VerdictInputs inputs = readVerdictInputs(runDir.string());
    std::vector<SceneJudgement> judged;
    for (size_t si = 0; si < e.scenes.size(); ++si) judged.push_back(judgeRunScene(inputs, si, targets[si]));
    writeVerdictFiles(inputs, judged);
    std::cerr << verdictSummary(inputs, judged);
  }
  writeMeta(meta, e, runDir.string(), true);
  std::cerr << "log: " << (runDir / "log.csv").string() << "\n";
  if (o.report) {
    std::string problem = runReportScript(reportInterpreter(o.python), runDir.string(), o.mixedMachines);
    if (!problem.empty())
      std::cerr << "warning: no report: " << problem << "; the log is complete: " << (runDir / "log.csv").string()
                << "\n";
    else
      std::cerr << "plot:   " << (runDir / "rmse_vs_time.png").string() << "\nreport: "
                << (runDir / "report.html").string() << "\n";
  }
  std::fprintf(stderr, "finish: %.3f s from the last run's end to the finished %s\n",
               std::chrono::duration<double>(Clock::now() - lastRunEnd).count(), o.report ? "report" : "log");
  return runDir.string();
}


}  // namespace lb
