// Experiments that run until decided (verdict/sequential.h), simulated on
// synthetic scenes: the schedule, stopping when decided, not stopping when
// not, and the false-decision rate of the whole sequential procedure on
// identical configurations, with and without the Bonferroni split of the
// level among the looks.
#include <gtest/gtest.h>
#include <cstdio>
#include "experiments/verdict/sequential.h"
#include "synthetic.h"

namespace lb {
namespace {

using synthetic::Config;

TEST(Sequential, Schedules) {
  RepeatPlan fixed;
  fixed.repeats = 3;
  EXPECT_EQ(fixed.looks(), (std::vector<int>{3}));
  RepeatPlan plan;
  plan.untilDecided = true, plan.min = 2, plan.repeats = 16;
  EXPECT_EQ(plan.looks(), (std::vector<int>{2, 4, 8, 16}));
  plan.min = 3, plan.repeats = 10;
  EXPECT_EQ(plan.looks(), (std::vector<int>{3, 6, 10}));
  plan.min = 4, plan.repeats = 4;
  EXPECT_EQ(plan.looks(), (std::vector<int>{4}));
}

// A simulated experiment: each configuration's repeats are drawn when the
// runner asks for them (and kept, as the run folder keeps them).
struct Simulation {
  synthetic::Scene scene;
  std::vector<Config> configs;
  std::vector<std::vector<Image>> images;
  std::mt19937_64 rng;
  std::vector<std::vector<int>> rendered;  // each look's targets
  VerdictSettings settings;

  Simulation(std::vector<Config> c, uint64_t seed, int size = 6) : configs(std::move(c)), images(configs.size()), rng(seed) {
    scene = synthetic::makeScene(size, size, 64, 0.01, rng);
    settings.rankBy = "rmse";
  }
  RepeatTargets run(const RepeatPlan& plan, bool splitAmongLooks = true) {
    settings.looks = splitAmongLooks ? int(plan.looks().size()) : 1;
    auto render = [&](const RepeatTargets& t) {
      rendered.push_back(t[0]);
      for (size_t c = 0; c < configs.size(); ++c)
        while (int(images[c].size()) < t[0][c])
          images[c].push_back(synthetic::noisyImage(scene.truth, configs[c].sigma, configs[c].bias, rng));
    };
    auto judge = [&](size_t, const std::vector<int>& repeats) { return judged(repeats); };
    return runLooks(plan, 1, configs.size(), render, judge, [](size_t) {});
  }
  JudgedScene judged(const std::vector<int>& repeats) {
    SceneEvidence e;
    e.reference = scene.reference, e.referenceVariance = scene.variance, e.referenceChunks = scene.chunks;
    JudgedScene j;
    for (size_t c = 0; c < configs.size(); ++c) {
      ConfigurationEvidence ce;
      ce.label = "c" + std::to_string(c);
      ce.finals.assign(images[c].begin(), images[c].begin() + repeats[c]);
      ce.seconds.assign(size_t(repeats[c]), 1.0);
      e.configurations.push_back(ce);
      j.configurationOf.push_back(c);
    }
    j.verdict = judgeScene(e, settings);
    return j;
  }
};

RepeatPlan untilDecided(int min, int max) {
  RepeatPlan p;
  p.untilDecided = true, p.min = min, p.repeats = max;
  return p;
}

TEST(Sequential, StopsAtTheFirstLookWhenEverythingIsDecided) {
  Simulation sim({Config{0.01}, Config{0.05}, Config{0.25}}, 1, 16);  // MSEs 25× apart
  RepeatTargets t = sim.run(untilDecided(4, 16));
  EXPECT_EQ(sim.rendered.size(), 1u) << "a second look was rendered";
  EXPECT_EQ(t[0], (std::vector<int>{4, 4, 4}));
}

// Whatever the seed: an adjacent pair still undecided at the end had the
// schedule's maximum of repeats on both sides; the clear winner (the first,
// its MSE 100× lower) is decided at the first look and never extended.
TEST(Sequential, ExtendsOnlyWhatIsUndecidedAndNeverStopsEarly) {
  int extended = 0;
  for (uint64_t seed = 0; seed < 50; ++seed) {
    Simulation sim({Config{0.01}, Config{0.1}, Config{0.1 * std::sqrt(1.15)}}, 100 + seed);
    RepeatTargets t = sim.run(untilDecided(4, 16));
    JudgedScene last = sim.judged(t[0]);
    for (const auto& p : last.verdict.pairs)
      if (p.adjacent && !p.decided) {
        EXPECT_EQ(t[0][p.a], 16) << seed;
        EXPECT_EQ(t[0][p.b], 16) << seed;
      }
    EXPECT_EQ(t[0][0], 4) << "the clear winner needs no more repeats (seed " << seed << ")";
    extended += t[0][1] > 4;
  }
  EXPECT_GT(extended, 40) << "a 15 % difference is rarely decided with four repeats";
}

// Identical configurations judged at every look: with the level split among
// the looks, any false decision at any look happens in at most 5 % of seeds
// (within binomial error), for three configurations and 4 looks (2…16
// repeats) and for two and 6 looks (2…64). Judging every look at the full
// level would not keep that: the looks are so many chances to err.
TEST(Sequential, FalseDecisionRateStaysAtTheNominalLevel) {
  const int seeds = 400;
  struct Case {
    int configs, max;
  };
  for (Case c : {Case{3, 16}, Case{2, 64}})
    for (bool split : {true, false}) {
      int falseDecisions = 0;
      for (int seed = 0; seed < seeds; ++seed) {
        Simulation sim(std::vector<Config>(size_t(c.configs), Config{0.1}), 5000 + seed);
        RepeatPlan plan = untilDecided(2, c.max);
        RepeatTargets t = sim.run(plan, split);
        // A look ends the loop early only when everything is decided; the
        // last look's verdict is the report's.
        bool any = sim.rendered.size() < plan.looks().size() || synthetic::anyDecided(sim.judged(t[0]).verdict);
        falseDecisions += any;
      }
      double rate = double(falseDecisions) / seeds;
      std::printf("%d identical configurations, %zu looks, level %s: a false decision in %.1f %% of %d seeds\n",
                  c.configs, untilDecided(2, c.max).looks().size(), split ? "split among them" : "not split",
                  100 * rate, seeds);
      if (split) {
        EXPECT_LE(rate, synthetic::upperAllowance(0.05, seeds));
      } else if (c.configs == 2) {
        EXPECT_GT(rate, synthetic::upperAllowance(0.05, seeds)) << "the split is needed";
      }
    }
}

// A pair held back by the reference's noise (over half its variance):
// with extend_reference the look doubles the reference and adds no repeats;
// without it, repeats. runLooks then judges again at the next look.
TEST(Sequential, ReferenceDominatedPairsExtendTheReference) {
  JudgedScene scene;
  scene.configurationOf = {0, 1};
  PairComparison p;
  p.a = 0, p.b = 1, p.adjacent = true, p.decided = false, p.difference = 0.1, p.low = -0.1, p.high = 0.3;
  p.referenceShare = 0.8;
  scene.verdict.pairs = {p};
  LookDecision d = decideLook(scene, {4, 4}, 8, true);
  EXPECT_TRUE(d.extendReference);
  EXPECT_TRUE(d.extend.empty());
  d = decideLook(scene, {4, 4}, 8, false);
  EXPECT_FALSE(d.extendReference);
  EXPECT_EQ(d.extend, (std::set<size_t>{0, 1}));
  EXPECT_TRUE(decideLook(scene, {8, 8}, 0, true).extend.empty()) << "nothing after the last look";

  RepeatPlan plan = untilDecided(4, 16);
  plan.extendReference = true;
  int looks = 0, extensions = 0;
  RepeatTargets t = runLooks(
      plan, 1, 2, [&](const RepeatTargets&) { ++looks; },
      [&](size_t, const std::vector<int>&) {
        JudgedScene j = scene;
        j.verdict.pairs[0].decided = extensions > 0;  // the longer reference decides it
        return j;
      },
      [&](size_t) { ++extensions; });
  EXPECT_EQ(extensions, 1);
  EXPECT_EQ(looks, 2);
  EXPECT_EQ(t[0], (std::vector<int>{4, 4}));
}

TEST(Sequential, ReasonsNameWhatKeepsAPairUndecided) {
  RepeatPlan plan = untilDecided(2, 8);
  PairComparison p;
  p.adjacent = true, p.difference = 0.1, p.low = -0.2, p.high = 0.4;
  p.referenceShare = 0.7;
  EXPECT_NE(undecidedReason(p, 2, 2, plan).find("the reference: its noise is 70 %"), std::string::npos);
  p.referenceShare = 0.1;
  EXPECT_NE(undecidedReason(p, 8, 8, plan).find("maximum of 8 repeats"), std::string::npos);
  EXPECT_NE(undecidedReason(p, 2, 2, RepeatPlan{}).find("until_decided: true"), std::string::npos);
  p.difference = 0, p.low = p.high = 0;
  EXPECT_NE(undecidedReason(p, 2, 2, plan).find("identical"), std::string::npos);
  p.decided = true;
  EXPECT_EQ(undecidedReason(p, 2, 2, plan), "");
}

}  // namespace
}  // namespace lb
