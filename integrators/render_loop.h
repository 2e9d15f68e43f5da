#pragma once
// Drives an integrator: preprocess once, then passes until the budget is spent.
// A time budget stops before a pass that is predicted to overshoot it (the
// prediction is the mean duration of the passes so far), so equal-time
// comparisons stay honest; preprocessing counts inside the budget.
// At least one pass is always rendered, even when the preprocess alone used
// up the time budget: a black image with 0 spp would be scored as a result.
// The report then says by how much the budget was exceeded, and every caller
// (the summary line, the experiment log) must show it.
#include <functional>
#include <string>
#include "integrators/adaptive_sampling.h"
#include "integrators/integrator.h"

namespace lb {

struct RenderBudget {
  uint64_t spp = 0;       // 0: no sample limit
  double seconds = 0;     // 0: no time limit
};

struct RenderOptions {
  // Setup done before the loop but owed to this render (the scene's BVH build
  // when the scene is shared between runs): added to its clock and preprocess.
  double setupSeconds = 0;
  uint64_t seed = 0;
  RenderBudget budget;
  bool progress = false;  // a progress line on stderr
  // Adaptive sampling (adaptive_sampling.h): the film then holds the
  // estimating half, and a pass is one pass's worth of samples.
  AdaptiveSettings adaptive;
};

struct RenderReport {
  uint64_t passes = 0;
  uint64_t rays = 0;
  double seconds = 0;            // preprocess + passes
  double preprocessSeconds = 0;
  uint64_t nonFinite = 0;
  double budgetSeconds = 0;      // the time budget it ran under (0: none)
  bool converged = false;        // adaptive sampling stopped: every pixel reached its target

  // Wall time beyond the time budget (0 without one, or within it).
  double overBudgetSeconds() const { return budgetSeconds > 0 ? std::max(0.0, seconds - budgetSeconds) : 0.0; }
  bool overBudget() const { return overBudgetSeconds() > 0; }
};

// "time budget 2 s exceeded by 7.6 s (preprocess alone took 9.1 s; at least one
// pass is always rendered)", or "" within the budget.
std::string overBudgetMessage(const RenderReport& report);

struct PassProgress {
  uint64_t passes;
  double seconds;            // preprocess + passes so far
  double preprocessSeconds;
};

// `afterPass` is called after each pass (snapshots); the time it takes is
// excluded from the clock and the budget.
RenderReport renderLoop(const Scene& scene, Integrator& integrator, Film& film, const SamplerSettings& sampler,
                        const RenderOptions& options,
                        const std::function<void(const PassProgress&)>& afterPass = {});

// Makes every TBB worker (and the caller) use flush-to-zero, as Embree asks.
void enableFlushToZeroOnAllThreads();

}  // namespace lb
