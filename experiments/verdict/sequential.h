#pragma once
// Experiments that run until the answer is known (issue 32):
//     repeats: {until_decided: true, min: 4, max: 16, extend_reference: false}
// The runner renders `min` repeats of every configuration, judges every
// scene (verdict.h), and gives the configurations of each adjacent pair
// that is still undecided the next number of repeats of the schedule
// min, 2·min, 4·min, …, max; where the reference's noise is most of such a
// pair's uncertainty and extend_reference is set, it doubles the reference's
// chunks instead of adding repeats. It stops when every
// adjacent pair of every scene is decided or the schedule ends.
//
// Looking at the data after every step and stopping when a test rejects
// would inflate the false decisions. The schedule fixes the number of looks
// L in advance, and every test and interval of the run is made at level
// (1 − confidence)/L (Bonferroni over the looks, on top of Holm over the
// pairs within a look), so the probability of any false decision at any look
// stays at most 1 − confidence. Simulated in tests/experiments/verdict/.
//
// min defaults to 4: two repeats give Welch's test about one degree of
// freedom (a Cauchy tail), so at a level split among looks and pairs a first
// look at 2 decides almost nothing and only spends its share of the level.
#include <functional>
#include <set>
#include <string>
#include <vector>
#include "experiments/verdict/verdict.h"

namespace lb {

struct RepeatPlan {
  int repeats = 1;  // `repeats: N`, or the schedule's maximum
  bool untilDecided = false;
  int min = 4;  // with 2, Welch's test has about one degree of freedom: see sequential.h
  bool extendReference = false;
  // The repeats at each look: {repeats} for a fixed count, else min,
  // 2·min, … (doubling) up to and ending with max (= repeats).
  std::vector<int> looks() const;
};

// One scene judged at a look: its verdict over the logged labels, and for
// each of them the configuration whose runs it is (a denoised label is its
// configuration's runs filtered).
struct JudgedScene {
  SceneVerdict verdict;
  std::vector<size_t> configurationOf;
};

// What a look decided for one scene.
struct LookDecision {
  std::set<size_t> extend;       // configurations to give more repeats
  bool extendReference = false;  // double the reference's chunks
};

// `repeats[c]`: configuration c's repeats so far; `nextRepeats`: the
// schedule's next count (0 after the last look).
LookDecision decideLook(const JudgedScene& scene, const std::vector<int>& repeats, int nextRepeats,
                        bool allowReferenceExtension);

// Why an adjacent pair is still undecided, for the report: the reference
// (its share of the difference's variance), identical results, or the runs'
// spread (and whether the schedule could have added repeats).
std::string undecidedReason(const PairComparison& pair, int repeatsA, int repeatsB, const RepeatPlan& plan);

// The loop itself, over every scene at once so that each look's runs can be
// rendered together: render(targets) makes sure repeats [0, targets[s][c])
// of every scene s and configuration c exist; judge(s, targets[s]) judges a
// scene; extendReference(s) doubles its reference. Returns the final targets.
using RepeatTargets = std::vector<std::vector<int>>;
RepeatTargets runLooks(const RepeatPlan& plan, size_t scenes, size_t configurations,
                       const std::function<void(const RepeatTargets&)>& render,
                       const std::function<JudgedScene(size_t scene, const std::vector<int>& repeats)>& judge,
                       const std::function<void(size_t scene)>& extendReference);

}  // namespace lb
