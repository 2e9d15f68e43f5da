#include "experiments/verdict/sequential.h"
#include <algorithm>
#include <cstdio>

namespace lb {

std::vector<int> RepeatPlan::looks() const {
  if (!untilDecided) return {repeats};
  std::vector<int> out;
  for (int r = std::max(1, min); r < repeats; r *= 2) out.push_back(r);
  out.push_back(repeats);
  return out;
}

namespace {
// Above this share of a pair's variance the reference, not the runs, keeps it undecided.
constexpr double ReferenceDominates = 0.5;
}  // namespace

LookDecision decideLook(const JudgedScene& scene, const std::vector<int>& repeats, int nextRepeats,
                        bool allowReferenceExtension) {
  LookDecision d;
  if (nextRepeats <= 0) return d;
  for (const PairComparison& p : scene.verdict.pairs) {
    if (!p.adjacent || p.decided) continue;
    // Identical images (two labels for one configuration) stay tied however
    // many repeats are added: both sides render the same seeds.
    if (p.difference == 0 && p.high == p.low) continue;
    if (allowReferenceExtension && p.referenceShare > ReferenceDominates) {
      d.extendReference = true;
      continue;
    }
    for (size_t entry : {p.a, p.b}) {
      size_t c = scene.configurationOf[entry];
      if (repeats[c] < nextRepeats) d.extend.insert(c);
    }
  }
  return d;
}

std::string undecidedReason(const PairComparison& p, int repeatsA, int repeatsB, const RepeatPlan& plan) {
  if (p.decided) return "";
  char buf[256];
  if (p.difference == 0 && p.high == p.low) return "identical results (the same images)";
  if (p.referenceShare > ReferenceDominates) {
    std::snprintf(buf, sizeof buf,
                  "the reference: its noise is %.0f %% of the difference's variance (a longer reference, or "
                  "repeats: {until_decided: true, extend_reference: true})",
                  100 * p.referenceShare);
    return buf;
  }
  int most = std::max(repeatsA, repeatsB);
  if (plan.untilDecided && most >= plan.repeats)
    std::snprintf(buf, sizeof buf, "the runs' spread, at the schedule's maximum of %d repeats", plan.repeats);
  else if (plan.untilDecided)
    std::snprintf(buf, sizeof buf, "the runs' spread (%d and %d repeats)", repeatsA, repeatsB);
  else
    std::snprintf(buf, sizeof buf,
                  "the runs' spread (%d and %d repeats; repeats: {until_decided: true} adds repeats until decided)",
                  repeatsA, repeatsB);
  return buf;
}

RepeatTargets runLooks(const RepeatPlan& plan, size_t scenes, size_t configurations,
                       const std::function<void(const RepeatTargets&)>& render,
                       const std::function<JudgedScene(size_t scene, const std::vector<int>& repeats)>& judge,
                       const std::function<void(size_t scene)>& extendReference) {
  const std::vector<int> looks = plan.looks();
  RepeatTargets targets(scenes, std::vector<int>(configurations, looks[0]));
  for (size_t look = 0; look < looks.size(); ++look) {
    render(targets);
    if (look + 1 == looks.size()) break;
    bool more = false;
    for (size_t s = 0; s < scenes; ++s) {
      LookDecision d = decideLook(judge(s, targets[s]), targets[s], looks[look + 1], plan.extendReference);
      for (size_t c : d.extend) targets[s][c] = looks[look + 1];
      if (d.extendReference) extendReference(s);
      more = more || !d.extend.empty() || d.extendReference;
    }
    if (!more) break;
  }
  return targets;
}

}  // namespace lb
