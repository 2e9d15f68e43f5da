#include "experiments/runner.h"
#include "experiments/report_step.h"
#include <tbb/info.h>
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
#include "core/aov.h"
#include "core/denoise.h"
#include "core/scene_loader.h"
#include "experiments/decomposition.h"
#include "experiments/meta.h"
#include "experiments/reference.h"
#include "experiments/run_lock.h"
#include "experiments/validate.h"
#include "integrators/registry.h"

namespace fs = std::filesystem;

namespace lb {

const char* const LogColumns[] = {"scene", "label", "integrator", "repeat", "seed", "time_s", "preprocess_s", "spp",
                                  "rmse", "relmse", "mape", "variance", "nonfinite", "rmse_crop", "relmse_crop",
                                  "mape_crop", "over_budget_s", "final", nullptr};

namespace {

// Jittered first-hit rays per pixel for the denoiser's features (core/aov.h).
constexpr int DenoiseFeatureSamples = 16;

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

// Splits one CSV line (RFC 4180 quoting); returns false on a torn line.
bool parseCsvLine(const std::string& line, std::vector<std::string>& out) {
  out.clear();
  std::string field;
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') field += '"', ++i;
      else if (c == '"') quoted = false;
      else field += c;
    } else if (c == '"') quoted = true;
    else if (c == ',') out.push_back(field), field.clear();
    else field += c;
  }
  out.push_back(field);
  return !quoted;
}

size_t columnCount() {
  size_t n = 0;
  while (LogColumns[n]) ++n;
  return n;
}

std::string runKey(const std::string& scene, const std::string& label, const std::string& repeat) {
  return scene + "\x1f" + label + "\x1f" + repeat;
}

// log.csv, appended and flushed row by row. On resume, rows of runs that did
// not finish (no final row) and torn lines are dropped; finished runs stay.
class LogWriter {
 public:
  LogWriter(const std::string& path, bool resume, std::set<std::string>* completed) {
    std::vector<std::string> kept;
    if (resume && fs::exists(path)) {
      std::ifstream in(path);
      std::string line;
      std::vector<std::vector<std::string>> rows;
      std::getline(in, line);  // header
      std::vector<std::string> f;
      while (std::getline(in, line))
        if (parseCsvLine(line, f) && f.size() == columnCount()) rows.push_back(f), kept.push_back(line);
      for (const auto& r : rows)
        if (r.back() == "1") completed->insert(runKey(r[0], r[1], r[3]));
      std::vector<std::string> filtered;
      for (size_t i = 0; i < rows.size(); ++i)
        if (completed->count(runKey(rows[i][0], rows[i][1], rows[i][3]))) filtered.push_back(kept[i]);
      kept = filtered;
    }
    std::string header;
    for (size_t i = 0; LogColumns[i]; ++i) header += (i ? "," : "") + std::string(LogColumns[i]);
    std::string content = header + "\n";
    for (const auto& l : kept) content += l + "\n";
    writeTextFile(path, content);
    out_.open(path, std::ios::app);
  }
  void write(const std::vector<std::string>& fields) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (size_t i = 0; i < fields.size(); ++i) out_ << (i ? "," : "") << csvField(fields[i]);
    out_ << "\n";
    out_.flush();
  }

 private:
  std::ofstream out_;
  std::mutex mutex_;
};

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(9);
  s << v;
  return s.str();
}

std::string formatDuration(double s) {
  char buf[32];
  if (s < 60) std::snprintf(buf, sizeof buf, "%.0fs", s);
  else std::snprintf(buf, sizeof buf, "%dm%02ds", int(s) / 60, int(s) % 60);
  return buf;
}

struct RunTask {
  size_t scene, config;
  int repeat;
};

// Snapshot points: log- or linearly spaced in time (time budget) or in passes.
std::vector<double> snapshotPoints(const Experiment& e) {
  double total = e.budget.seconds > 0 ? e.budget.seconds : double(e.budget.spp);
  std::vector<double> points;
  for (int k = 0; k < e.snapshots; ++k) {
    double t = e.spacing == SnapshotSpacing::Log ? total * std::pow(2.0, k - (e.snapshots - 1))
                                                 : total * (k + 1) / e.snapshots;
    if (e.budget.seconds <= 0) t = std::max(1.0, std::round(t));
    if (points.empty() || t > points.back()) points.push_back(t);
  }
  return points;
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

// Repeat 0's image is <stem>.exr (shown in the report), repeat r's <stem>__repeat<r>.exr.
std::string repeatImagePath(const std::string& stem, int repeat) {
  return repeat == 0 ? stem + ".exr" : stem + "__repeat" + std::to_string(repeat) + ".exr";
}

// decomposition.csv: each configuration's final MSE split into bias² and
// variance over its repeats, with 95 % intervals (experiments/decomposition.h).
// Read back from the run folder, so a resumed run includes the earlier runs.
void writeDecomposition(const Experiment& e, const fs::path& runDir, const std::vector<Image>& references,
                        const std::vector<Image>& referenceVariances) {
  std::ostringstream csv;
  csv << "scene,label,integrator,repeats,mse,bias2,bias2_low,bias2_high,variance,variance_low,variance_high,"
         "reference_variance\n";
  for (size_t si = 0; si < e.scenes.size(); ++si)
    for (const auto& c : e.configurations) {
      std::string stem = (runDir / (e.scenes[si].name + "__" + slug(c.label))).string();
      // The repeats whose images are there: a run resumed from a folder that
      // a version without them started has fewer. Never fails the run.
      std::vector<Image> finals;
      for (int r = 0; r < e.repeats; ++r)
        if (fs::exists(repeatImagePath(stem, r))) finals.push_back(readExr(repeatImagePath(stem, r)));
      if (finals.size() < 2) {
        std::cerr << "warning: " << e.scenes[si].name << " / " << c.label << ": " << finals.size()
                  << " final image(s) of its repeats in the run folder; no bias²/variance split\n";
        continue;
      }
      ErrorDecomposition d = decomposeError(finals, references[si], referenceVariances[si]);
      csv << csvField(e.scenes[si].name) << "," << csvField(c.label) << "," << c.integrator << "," << d.repeats;
      // An unknown reference variance (a given EXR) is an empty field: bias²
      // then includes it (the report says so).
      for (double v : {d.mse, d.bias2, d.bias2Low, d.bias2High, d.variance, d.varianceLow, d.varianceHigh,
                       d.referenceVariance})
        csv << "," << (std::isfinite(v) ? fmt(v) : "");
      csv << "\n";
    }
  writeTextFile((runDir / "decomposition.csv").string(), csv.str());
}

}  // namespace

std::string runExperiment(const Experiment& e, const RunnerOptions& o) {
  using Clock = std::chrono::steady_clock;
  // Every input first: a bad one fails in seconds, before any reference
  // renders, and leaves no run folder behind.
  CheckedExperiment checked = validateExperiment(e);

  // What a resumed run must share with the one it continues.
  std::vector<std::string> identity = {YAML::Dump(e.source), std::to_string(e.budget.seconds),
                                       std::to_string(e.budget.spp), std::to_string(e.repeats)};
  // Each reference's key hashes its scene and mesh files: computed once here.
  std::vector<std::string> referenceIds;
  for (const auto& s : e.scenes) referenceIds.push_back(s.reference.file.empty() ? referenceKey(s) : s.reference.file);
  identity.insert(identity.end(), referenceIds.begin(), referenceIds.end());
  std::string experimentHash = hashStrings(identity);
  fs::path runDir = latestRun(e, o);
  std::optional<RunLock> lock;
  if (!runDir.empty()) {
    if (fs::exists(runDir / "meta.json")) {
      if (readExperimentHash(runDir.string()) != experimentHash)
        throw ConfigError(e.file, 0, "--resume",
                          "the experiment, its budget or its references changed since " + runDir.string() +
                              " was started; run without --resume to start a new run");
    }
    // Before anything is rendered or rewritten: one writer per run folder.
    lock.emplace(runDir.string(), e.file);
  }

  // References (rendered with every core) before the run folder exists: a
  // reference that fails leaves no half-started run.
  std::vector<Image> references, referenceVariances;
  std::vector<double> referenceFloors;
  std::vector<std::string> referenceDescriptions;
  for (size_t si = 0; si < e.scenes.size(); ++si) {
    const ExperimentScene& s = e.scenes[si];
    Reference obtained;
    if (!s.reference.file.empty()) {
      std::cerr << "reference: " << s.reference.file << " (given)\n";
      obtained.image = std::move(checked.givenReferences[si]);
    } else {
      obtained = obtainReference(s, o.resultsRoot, referenceIds[si]);
    }
    const Camera& camera = checked.scenes[si].scene->camera;
    // A given EXR of another size is refused before this; a safety net.
    if (obtained.image.width != camera.width() || obtained.image.height != camera.height())
      throw s.referenceAt.error("reference of " + s.name + " is " + std::to_string(obtained.image.width) + "×" +
                                std::to_string(obtained.image.height) + ", the scene renders " +
                                std::to_string(camera.width()) + "×" + std::to_string(camera.height()));
    references.push_back(std::move(obtained.image));
    referenceVariances.push_back(std::move(obtained.variance));
    referenceDescriptions.push_back(obtained.description.empty() ? "file " + s.reference.file : obtained.description);
    referenceFloors.push_back(std::sqrt(obtained.varianceOfMean));
  }
  std::vector<SceneFile>& scenes = checked.scenes;

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
  std::cerr << "experiment '" << e.name << "': " << runDir.string() << (o.resume ? " (resuming)" : "") << "\n";

  std::set<std::string> completed;
  LogWriter log((runDir / "log.csv").string(), o.resume, &completed);

  int cores = tbb::info::default_concurrency();
  int jobs = std::max(1, std::min(o.jobs, cores));
  int threadsPerRun = std::max(1, cores / jobs);
  RunMeta meta = startMeta(e, runDir.string(), threadsPerRun, jobs, experimentHash);
  for (size_t si = 0; si < e.scenes.size(); ++si) {
    const ExperimentScene& s = e.scenes[si];
    meta.referenceRmseFloor[s.name] = referenceFloors[si];
    meta.referenceKeys[s.name] = referenceIds[si];
    meta.referenceUsed[s.name] = referenceDescriptions[si];
    // The reference beside the run's images: the folder is complete for
    // lightbench.load_run and the report's viewer.
    writeExr((runDir / (s.name + "__reference.exr")).string(), references[si]);
    writePng((runDir / (s.name + "__reference.png")).string(), references[si]);
    if (!s.crop.empty())
      writePng((runDir / (s.name + "__reference_crop.png")).string(), cropImage(references[si], s.crop, 4));
  }

  std::vector<RunTask> tasks;
  for (size_t si = 0; si < e.scenes.size(); ++si)
    for (size_t ci = 0; ci < e.configurations.size(); ++ci)
      for (int r = 0; r < e.repeats; ++r)
        if (!completed.count(runKey(e.scenes[si].name, e.configurations[ci].label, std::to_string(r))))
          tasks.push_back({si, ci, r});
  size_t totalRuns = e.scenes.size() * e.configurations.size() * size_t(e.repeats);
  if (tasks.size() < totalRuns) std::cerr << "resume: " << totalRuns - tasks.size() << " of " << totalRuns << " runs already complete\n";

  std::vector<double> points = snapshotPoints(e);
  bool timeBudget = e.budget.seconds > 0;
  std::atomic<size_t> next{0};
  std::mutex progressMutex;
  auto experimentStart = Clock::now();

  // Each configuration's parameters for each scene (an imported scene's
  // max_depth added), built here: merging YAML nodes writes to both sides,
  // so the workers below must only read them.
  std::vector<std::vector<YAML::Node>> runParams(e.scenes.size());
  for (size_t si = 0; si < e.scenes.size(); ++si)
    for (const Configuration& c : e.configurations) runParams[si].push_back(withSharedIntegratorKeys(scenes[si], c.params));

  auto runOne = [&](const RunTask& t) {
    const ExperimentScene& es = e.scenes[t.scene];
    const Configuration& c = e.configurations[t.config];
    const Image& ref = references[t.scene];
    const Scene& scene = *scenes[t.scene].scene;
    // An imported scene's max_depth holds for every configuration (the integral it defines).
    Params params(runParams[t.scene][t.config], e.file, c.context);
    auto integrator = makeIntegrator(c.integrator, params);
    if (!c.denoise.empty() && !integrator->independentPasses())
      throw c.denoiseAt.error("'" + c.integrator + "' has correlated passes, so its film has no per-pixel variance, "
                              "which the filter measures colour differences in; remove denoise");
    Film film(scene.camera.width(), scene.camera.height());
    uint64_t seed = e.seed + uint64_t(t.repeat) * 7919;
    RenderOptions ro;
    ro.seed = seed;
    ro.budget = e.budget;
    ro.adaptive = c.adaptive;
    ro.setupSeconds = scene.buildSeconds();  // the BVH, built once per scene, is owed to every run
    size_t nextPoint = 0;
    // Seconds beyond a time budget: every integrator renders at least one
    // pass, so a preprocess longer than the budget overruns it (empty
    // without a time budget).
    auto overBudget = [&](double seconds) { return timeBudget ? fmt(std::max(0.0, seconds - e.budget.seconds)) : ""; };
    // denoise: the first-hit features, rendered once (their time counts in
    // every denoised snapshot), and the filtered snapshot with its time.
    std::optional<FirstHitImages> features;
    double featureSeconds = 0;
    struct Denoised {
      Image image;
      double seconds = 0;  // features + filter
    };
    auto denoiseSnapshot = [&]() {
      auto start = Clock::now();
      if (!features) {
        features = renderFirstHitImages(scene, DenoiseFeatureSamples, seed);
        featureSeconds = std::chrono::duration<double>(Clock::now() - start).count();
        start = Clock::now();
      }
      Denoised d;
      d.image = denoiseNlMeans(film.image(), film.varianceOfMean(), *features);
      d.seconds = featureSeconds + std::chrono::duration<double>(Clock::now() - start).count();
      return d;
    };
    auto record = [&](uint64_t passes, double seconds, double preprocess, bool final, const Denoised* denoised) {
      Image img = film.image();
      if (denoised) {  // its row first: the raw final row marks the run finished
        ErrorMetrics dm = computeMetrics(denoised->image, ref, e.metricSettings);
        ErrorMetrics dc = es.crop.empty() ? ErrorMetrics{} : computeMetrics(denoised->image, ref, e.metricSettings, es.crop);
        log.write({es.name, c.denoisedLabel(), c.integrator, std::to_string(t.repeat), std::to_string(seed),
                   fmt(seconds + denoised->seconds), fmt(preprocess), std::to_string(passes), fmt(dm.rmse),
                   fmt(dm.relMse), fmt(dm.mape), fmt(std::nan("")), std::to_string(film.nonFiniteCount()),
                   es.crop.empty() ? "" : fmt(dc.rmse), es.crop.empty() ? "" : fmt(dc.relMse),
                   es.crop.empty() ? "" : fmt(dc.mape), overBudget(seconds), final ? "1" : "0"});
      }
      ErrorMetrics m = computeMetrics(img, ref, e.metricSettings);
      ErrorMetrics mc = es.crop.empty() ? ErrorMetrics{} : computeMetrics(img, ref, e.metricSettings, es.crop);
      log.write({es.name, c.label, c.integrator, std::to_string(t.repeat), std::to_string(seed), fmt(seconds),
                 fmt(preprocess), std::to_string(passes), fmt(m.rmse), fmt(m.relMse), fmt(m.mape),
                 fmt(film.meanVarianceOfMean()), std::to_string(film.nonFiniteCount()),
                 es.crop.empty() ? "" : fmt(mc.rmse), es.crop.empty() ? "" : fmt(mc.relMse),
                 es.crop.empty() ? "" : fmt(mc.mape), overBudget(seconds), final ? "1" : "0"});
      std::lock_guard<std::mutex> lock(progressMutex);
      double elapsed = std::chrono::duration<double>(Clock::now() - experimentStart).count();
      // Per run: the time budget, or (sample budgets) the mean of finished runs.
      double perRun = timeBudget ? e.budget.seconds : (done > 0 ? elapsed / double(done) : 0);
      double eta = perRun > 0 ? perRun * double(tasks.size() - done) / jobs - (final ? 0 : seconds) : 0;
      std::string over = timeBudget && seconds > e.budget.seconds
                             ? " OVER BUDGET by " + fmt(seconds - e.budget.seconds) + "s"
                             : "";
      std::fprintf(stderr, "[run %zu/%zu] %s / %-22s repeat %d  snapshot %zu/%zu  t=%.2fs spp=%llu RMSE=%.4g%s%s  (elapsed %s%s)\n",
                   done.load() + 1, tasks.size(), es.name.c_str(), ("'" + c.label + "'").c_str(), t.repeat + 1,
                   final ? points.size() : nextPoint, points.size(), seconds, (unsigned long long)passes, m.rmse,
                   final ? " final" : "", over.c_str(), formatDuration(elapsed).c_str(),
                   eta > 0 ? (", ETA " + formatDuration(eta)).c_str() : "");
    };
    auto afterPass = [&](const PassProgress& p) {
      double at = timeBudget ? p.seconds : double(p.passes);
      bool due = false;
      while (nextPoint + 1 < points.size() && at >= points[nextPoint]) ++nextPoint, due = true;
      if (!due) return;
      std::optional<Denoised> d;
      if (!c.denoise.empty()) d = denoiseSnapshot();
      record(p.passes, p.seconds, p.preprocessSeconds, false, d ? &*d : nullptr);
    };
    RenderReport rep = renderLoop(scene, *integrator, film, c.sampler ? *c.sampler : scenes[t.scene].sampler, ro, afterPass);
    // Images first, the final row last: a run counts as finished (for
    // --resume) only once everything it produces is on disk.
    std::string stem = (runDir / (es.name + "__" + slug(c.label))).string();
    std::optional<Denoised> denoised;
    if (!c.denoise.empty()) denoised = denoiseSnapshot();
    auto writeImages = [&](const std::string& stem, const Image& img) {
      writeExr(stem + ".exr", img);
      writePng(stem + ".png", img);
      Image err = falseColour(relativeErrorImage(img, ref, e.metricSettings.relEpsilon), 1e-4f, 10.f);
      writePng(stem + "_error.png", err);
      if (!es.crop.empty()) {
        writePng(stem + "_crop.png", cropImage(img, es.crop, 4));
        writePng(stem + "_error_crop.png", cropImage(err, es.crop, 4));
      }
    };
    // Every repeat's final image, for the bias²/variance split over repeats.
    if (t.repeat > 0) writeExr(repeatImagePath(stem, t.repeat), film.image());
    if (t.repeat == 0) writeImages(stem, film.image());
    if (denoised && t.repeat == 0) writeImages((runDir / (es.name + "__" + slug(c.denoisedLabel()))).string(), denoised->image);
    record(rep.passes, rep.seconds, rep.preprocessSeconds, true, denoised ? &*denoised : nullptr);
    ++done;
  };

  std::exception_ptr failure;
  std::mutex failureMutex;
  auto worker = [&] {
    // A task arena takes the floating-point mode of the thread that creates
    // it: set flush-to-zero first, so every run traces in the same mode.
    enableFlushToZeroOnAllThreads();
    tbb::task_arena arena(threadsPerRun);
    try {
      for (size_t i; (i = next++) < tasks.size();) arena.execute([&] { runOne(tasks[i]); });
    } catch (...) {
      std::lock_guard<std::mutex> lock(failureMutex);
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
  discard.keep = true;

  if (e.repeats > 1) writeDecomposition(e, runDir, references, referenceVariances);
  finishMeta(meta, e, runDir.string());
  std::cerr << "log: " << (runDir / "log.csv").string() << "\n";
  if (o.report) {
    std::string problem = runReportScript(reportInterpreter(o.python), runDir.string());
    if (!problem.empty())
      std::cerr << "warning: no report: " << problem << "; the log is complete: " << (runDir / "log.csv").string()
                << "\n";
    else
      std::cerr << "plot:   " << (runDir / "rmse_vs_time.png").string() << "\nreport: "
                << (runDir / "report.html").string() << "\n";
  }
  return runDir.string();
}

}  // namespace lb
