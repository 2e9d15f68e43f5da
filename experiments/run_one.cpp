#include "experiments/run_one.h"
#include <chrono>
#include <cmath>
#include "core/aov.h"
#include "core/denoise.h"
#include "experiments/run_log.h"
#include "experiments/validate.h"
#include "integrators/registry.h"

namespace lb {

namespace {

using Clock = std::chrono::steady_clock;

// Jittered first-hit rays per pixel for the denoiser's features (core/aov.h).
constexpr int DenoiseFeatureSamples = 16;

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

}  // namespace

RunEnvironment makeRunEnvironment(const Experiment& e, const std::vector<SceneFile>& scenes,
                                  const MachineColumns& machine) {
  RunEnvironment env;
  env.experiment = &e;
  env.scenes = &scenes;
  env.params.resize(e.scenes.size());
  // Merging YAML nodes writes to both sides: built here, so runs only read them.
  for (size_t si = 0; si < e.scenes.size(); ++si)
    for (const Configuration& c : e.configurations)
      env.params[si].push_back(withSharedIntegratorKeys(scenes[si], c.params, keysReadBy(c.integrator)));
  env.snapshots = snapshotPoints(e);
  env.machine = machine;
  return env;
}

std::string repeatImagePath(const std::string& stem, int repeat) {
  return repeat == 0 ? stem + ".exr" : stem + "__repeat" + std::to_string(repeat) + ".exr";
}

RunOutcome performRun(const RunEnvironment& env, const RunTask& t, const Image& ref, const Image& refVariance,
                      const std::function<void(std::vector<std::string>&&)>& row,
                      const std::function<void(const RunProgress&)>& progress) {
  const Experiment& e = *env.experiment;
  const ExperimentScene& es = e.scenes[t.scene];
  const Configuration& c = e.configurations[t.config];
  const SceneFile& sf = (*env.scenes)[t.scene];
  const Scene& scene = *sf.scene;
  const std::vector<double>& points = env.snapshots;
  const bool timeBudget = e.budget.seconds > 0;
  // An imported scene's max_depth holds for every configuration that has a depth (the integral it defines).
  Params params(env.params[t.scene][t.config], e.file, c.context);
  auto integrator = makeIntegrator(c.integrator, params);
  if (!c.denoise.empty() && !integrator->independentPasses())
    throw c.denoiseAt.error("'" + c.integrator +
                            "' has correlated passes, so its film has no per-pixel variance, "
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
  auto overBudget = [&](double seconds) {
    return timeBudget ? logNumber(std::max(0.0, seconds - e.budget.seconds)) : "";
  };
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
  const MachineColumns& m = env.machine;
  auto makeRow = [&](const std::string& label, const Image& img, double seconds, double preprocess, uint64_t passes,
                     double variance, bool final, double* rmse) {
    ErrorMetrics em = computeMetrics(img, ref, e.metricSettings, {}, refVariance);
    ErrorMetrics mc = es.crop.empty() ? ErrorMetrics{} : computeMetrics(img, ref, e.metricSettings, es.crop, refVariance);
    if (rmse) *rmse = em.rmse;
    return std::vector<std::string>{es.name,
                                    label,
                                    c.integrator,
                                    std::to_string(t.repeat),
                                    std::to_string(seed),
                                    logNumber(seconds),
                                    logNumber(preprocess),
                                    std::to_string(passes),
                                    logNumber(em.rmse),
                                    logNumber(em.relMse),
                                    logNumber(em.mape),
                                    logNumber(variance),
                                    std::to_string(film.nonFiniteCount()),
                                    es.crop.empty() ? "" : logNumber(mc.rmse),
                                    es.crop.empty() ? "" : logNumber(mc.relMse),
                                    es.crop.empty() ? "" : logNumber(mc.mape),
                                    overBudget(seconds),
                                    m.host,
                                    m.cpu,
                                    std::to_string(m.threads),
                                    logNumber(em.relMseTrimmed),
                                    logNumber(em.mseCorrected),
                                    logNumber(em.relMseCorrected),
                                    logNumber(em.relMseTrimmedCorrected),
                                    es.crop.empty() ? "" : logNumber(mc.mseCorrected),
                                    es.crop.empty() ? "" : logNumber(mc.relMseCorrected),
                                    final ? "1" : "0"};
  };
  auto record = [&](uint64_t passes, double seconds, double preprocess, bool final, const Denoised* denoised) {
    if (denoised)  // its row first: the raw final row marks the run finished
      row(makeRow(c.denoisedLabel(), denoised->image, seconds + denoised->seconds, preprocess, passes, std::nan(""),
                  final, nullptr));
    RunProgress p;
    row(makeRow(c.label, film.image(), seconds, preprocess, passes, film.meanVarianceOfMean(), final, &p.rmse));
    p.snapshot = final ? points.size() : nextPoint;
    p.snapshots = points.size();
    p.seconds = seconds;
    p.passes = passes;
    p.final = final;
    progress(p);
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
  RenderReport rep = renderLoop(scene, *integrator, film, c.sampler ? *c.sampler : sf.sampler, ro, afterPass);
  RunOutcome out;
  out.image = film.image();
  std::optional<Denoised> denoised;
  if (!c.denoise.empty()) denoised = denoiseSnapshot(), out.denoised = denoised->image;
  record(rep.passes, rep.seconds, rep.preprocessSeconds, true, denoised ? &*denoised : nullptr);
  return out;
}

void writeRunImages(const std::string& runDir, const Experiment& e, const RunTask& t, const RunOutcome& outcome,
                    const Image& ref) {
  const ExperimentScene& es = e.scenes[t.scene];
  const Configuration& c = e.configurations[t.config];
  std::string stem = runDir + "/" + es.name + "__" + slug(c.label);
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
  // Every repeat's final image (the denoised one too), for the verdict and
  // the bias²/variance split over repeats.
  std::string denoisedStem = runDir + "/" + es.name + "__" + slug(c.denoisedLabel());
  if (t.repeat > 0) {
    writeExr(repeatImagePath(stem, t.repeat), outcome.image);
    if (outcome.denoised) writeExr(repeatImagePath(denoisedStem, t.repeat), *outcome.denoised);
  } else {
    writeImages(stem, outcome.image);
    if (outcome.denoised) writeImages(denoisedStem, *outcome.denoised);
  }
}

}  // namespace lb
