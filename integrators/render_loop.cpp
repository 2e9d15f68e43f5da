#include "integrators/render_loop.h"
#include <tbb/task_scheduler_observer.h>
#include <unistd.h>
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include "core/format.h"

namespace lb {

namespace {
class FlushToZeroObserver final : public tbb::task_scheduler_observer {
 public:
  FlushToZeroObserver() { observe(true); }
  void on_scheduler_entry(bool) override { enableFlushToZero(); }
};

void printProgress(bool tty, double fraction, uint64_t passes, double samplesPerSecond, double raysPerSecond,
                   const std::string& tail) {
  std::fprintf(stderr, "%s[%3d%%] %llu spp, %s, %s, %s%s", tty ? "\r" : "", int(100 * std::min(1.0, fraction)),
               (unsigned long long)passes, formatCount(samplesPerSecond, "samples/s").c_str(),
               formatCount(raysPerSecond, "rays/s").c_str(), tail.c_str(), tty ? "   " : "\n");
  std::fflush(stderr);
}
}  // namespace

void enableFlushToZeroOnAllThreads() {
  static FlushToZeroObserver observer;
  enableFlushToZero();
}

std::string overBudgetMessage(const RenderReport& r) {
  if (!r.overBudget()) return "";
  char buf[200];
  int n = std::snprintf(buf, sizeof buf, "time budget %g s exceeded by %.3g s", r.budgetSeconds, r.overBudgetSeconds());
  if (r.preprocessSeconds >= r.budgetSeconds)
    std::snprintf(buf + n, sizeof buf - size_t(n), " (preprocess alone took %.3g s; at least one pass is always rendered)",
                  r.preprocessSeconds);
  return buf;
}

RenderReport renderLoop(const Scene& scene, Integrator& integrator, Film& film, const SamplerSettings& samplerSettings,
                        const RenderOptions& options, const std::function<void(const PassProgress&)>& afterPass) {
  using Clock = std::chrono::steady_clock;
  enableFlushToZeroOnAllThreads();
  auto sampler = makeSampler(samplerSettings, options.seed, scene.camera.width(), scene.camera.height());
  RenderReport report;
  auto start = Clock::now();
  double excluded = 0;  // time spent in afterPass (snapshot metrics): not the integrator's
  auto elapsed = [&] {
    return options.setupSeconds + std::chrono::duration<double>(Clock::now() - start).count() - excluded;
  };
  std::unique_ptr<AdaptiveSampling> adaptive;
  auto* pixelIntegrator = dynamic_cast<PixelIntegrator*>(&integrator);
  if (options.adaptive.enabled) {
    std::string why = integrator.adaptiveRefusal();
    if (!pixelIntegrator && why.empty()) why = "it does not estimate each pixel from its own camera samples";
    if (!why.empty()) throw std::invalid_argument("adaptive sampling: " + why);
    adaptive = std::make_unique<AdaptiveSampling>(film.width(), film.height(), options.adaptive);
  }
  integrator.setProgress(options.progress);
  integrator.preprocess(scene, *sampler);
  report.preprocessSeconds = elapsed();

  const RenderBudget& budget = options.budget;
  bool tty = options.progress && isatty(STDERR_FILENO);
  double lastPrint = -1;
  PassStats stats;
  for (uint64_t pass = 0;; ++pass) {
    if (budget.spp > 0 && pass >= budget.spp) break;
    // No time check before pass 0: even when preprocessing used the whole
    // budget, one pass is rendered (and the overrun reported), never 0 spp.
    if (budget.seconds > 0 && pass > 0) {
      double perPass = (elapsed() - report.preprocessSeconds) / double(pass);
      if (elapsed() + perPass > budget.seconds) break;
    }
    if (budget.spp == 0 && budget.seconds == 0 && pass > 0) break;  // no budget: one pass
    if (adaptive) {
      if (!adaptive->renderPass(scene, *pixelIntegrator, film, *sampler, pass, stats)) {
        report.converged = true;
        break;
      }
    } else {
      integrator.renderPass(scene, film, *sampler, pass, stats);
    }
    report.passes = pass + 1;
    double t = elapsed();
    if (afterPass) {
      auto before = Clock::now();
      afterPass({report.passes, t, report.preprocessSeconds});
      excluded += std::chrono::duration<double>(Clock::now() - before).count();
    }
    if (options.progress && (t - lastPrint > (tty ? 0.25 : 5.0))) {
      lastPrint = t;
      double fraction = budget.spp > 0 ? double(report.passes) / double(budget.spp) : 0;
      if (budget.seconds > 0) fraction = std::max(fraction, t / budget.seconds);
      double eta = fraction > 0 ? t / fraction - t : 0;
      double samplesPerSecond = double(report.passes) * film.width() * film.height() / std::max(t, 1e-9);
      printProgress(tty, fraction, report.passes, samplesPerSecond, double(stats.rays.load()) / std::max(t, 1e-9),
                    "ETA " + formatSeconds(eta));
    }
  }
  // The line ends at 100 %, whichever budget ended the loop.
  if (options.progress) {
    double t = elapsed();
    printProgress(tty, 1.0, report.passes, double(report.passes) * film.width() * film.height() / std::max(t, 1e-9),
                  double(stats.rays.load()) / std::max(t, 1e-9), "done in " + formatSeconds(t));
    if (tty) std::fprintf(stderr, "\n");
  }
  report.seconds = elapsed();
  report.budgetSeconds = budget.seconds;
  report.rays = stats.rays.load();
  report.nonFinite = film.nonFiniteCount();
  return report;
}

}  // namespace lb
