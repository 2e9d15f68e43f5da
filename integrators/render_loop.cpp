#include "integrators/render_loop.h"
#include <tbb/task_scheduler_observer.h>
#include <unistd.h>
#include <chrono>
#include <cstdio>

namespace lb {

namespace {
class FlushToZeroObserver final : public tbb::task_scheduler_observer {
 public:
  FlushToZeroObserver() { observe(true); }
  void on_scheduler_entry(bool) override { enableFlushToZero(); }
};

std::string formatSeconds(double s) {
  char buf[32];
  if (s < 120) std::snprintf(buf, sizeof buf, "%.1fs", s);
  else std::snprintf(buf, sizeof buf, "%dm%02ds", int(s) / 60, int(s) % 60);
  return buf;
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
  auto sampler = makeSampler(samplerSettings, options.seed);
  RenderReport report;
  auto start = Clock::now();
  double excluded = 0;  // time spent in afterPass (snapshot metrics): not the integrator's
  auto elapsed = [&] {
    return options.setupSeconds + std::chrono::duration<double>(Clock::now() - start).count() - excluded;
  };
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
    integrator.renderPass(scene, film, *sampler, pass, stats);
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
      std::fprintf(stderr, "%s[%3d%%] %llu spp, %.2f Msamples/s, %.2f Mrays/s, ETA %s%s", tty ? "\r" : "",
                   int(100 * std::min(1.0, fraction)), (unsigned long long)report.passes, samplesPerSecond * 1e-6,
                   double(stats.rays.load()) / std::max(t, 1e-9) * 1e-6, formatSeconds(eta).c_str(), tty ? "   " : "\n");
      std::fflush(stderr);
    }
  }
  if (tty) std::fprintf(stderr, "\n");
  report.seconds = elapsed();
  report.budgetSeconds = budget.seconds;
  report.rays = stats.rays.load();
  report.nonFinite = film.nonFiniteCount();
  return report;
}

}  // namespace lb
