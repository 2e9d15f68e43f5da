// The benchmark's cost split (integrators/bidirectional/cost_split.h): its
// phases partition a thread's time (nested scopes charge the inner phase, not
// both), every phase a renderer has is charged, and switching it on does not
// change an image.
#include <gtest/gtest.h>
#include <chrono>
#include <cstring>
#include <numeric>
#include "integrators/bidirectional/cost_split.h"
#include "tests/support/render_helpers.h"

namespace lb::test {
namespace {

using bidir::CostSplit;
using bidir::Phase;
using bidir::PhaseScope;
using Clock = std::chrono::steady_clock;

void spin(double seconds) {
  auto until = Clock::now() + std::chrono::duration<double>(seconds);
  while (Clock::now() < until) {
  }
}

double total(const std::array<double, bidir::PhaseCount>& s) { return std::accumulate(s.begin(), s.end(), 0.0); }

TEST(CostSplit, NestedPhasesPartitionTheTimeOfTheOutermost) {
  // Outer scope (connections) around an inner one (weights), one thread: the
  // phases sum to the outer scope's wall time, and the inner phase's time is
  // not counted in the outer's as well. (A scope that charged both would sum
  // to about 1.5 times the span; a clock conversion off by the ratio of two
  // clocks' rates would miss it too.) Wall time against ticks: the thread
  // being descheduled counts in both, so this holds on a busy machine.
  CostSplit::enable(true);
  auto start = Clock::now();
  {
    PhaseScope outer(Phase::Connections);
    spin(0.02);
    {
      PhaseScope inner(Phase::Weights);
      spin(0.04);
    }
    spin(0.02);
  }
  double span = std::chrono::duration<double>(Clock::now() - start).count();
  auto s = CostSplit::threadSeconds();
  CostSplit::enable(false);
  EXPECT_NEAR(total(s), span, 0.05 * span);
  EXPECT_GT(s[size_t(Phase::Weights)], 0.45 * span);   // the 40 ms of 80 ms within
  EXPECT_GT(s[size_t(Phase::Connections)], 0.35 * span);  // the 40 ms around it
  EXPECT_LT(s[size_t(Phase::Connections)], 0.6 * span);
}

TEST(CostSplit, ScopesDoNothingWhileItIsOff) {
  CostSplit::enable(true);  // resets the totals
  CostSplit::enable(false);
  {
    PhaseScope scope(Phase::Merges);
    spin(0.005);
  }
  EXPECT_EQ(total(CostSplit::threadSeconds()), 0.0);
}

// A render with the split on charges every phase its integrator has, stays
// within the threads' time, and gives the same image bit for bit as one
// without it.
void checkRender(const char* integrator, std::vector<Phase> expected) {
  SceneFile sf = loadShippedScene("caustic-glass-sphere", 24, 18);
  RenderSpec spec{integrator, "{max_depth: 6}", 8, 3, 2};
  Image off = renderScene(sf, spec)->image();
  CostSplit::enable(true);
  auto start = Clock::now();
  Image on = renderScene(sf, spec)->image();
  double wall = std::chrono::duration<double>(Clock::now() - start).count();
  auto s = CostSplit::threadSeconds();
  CostSplit::enable(false);
  EXPECT_EQ(std::memcmp(off.pixels.data(), on.pixels.data(), off.pixels.size() * sizeof(Color)), 0) << integrator;
  for (Phase p : expected) EXPECT_GT(s[size_t(p)], 0.0) << integrator << ": " << bidir::phaseName(p);
  EXPECT_LE(total(s), 2 * wall * 1.01) << integrator;  // two threads, no time counted twice
}

TEST(CostSplit, BdptChargesItsPhasesAndRendersTheSameImage) {
  checkRender("bdpt", {Phase::LightSubpaths, Phase::CameraSubpaths, Phase::Connections, Phase::Weights});
}

TEST(CostSplit, VcmChargesItsPhasesAndRendersTheSameImage) {
  checkRender("vcm", {Phase::LightSubpaths, Phase::Index, Phase::CameraSubpaths, Phase::Connections, Phase::Merges,
                      Phase::Weights});
}

}  // namespace
}  // namespace lb::test
