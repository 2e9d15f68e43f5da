// The Bernoulli estimate of 1/p that specular manifold sampling weighs each
// solution by (integrators/manifold/reciprocal_probability.h), on a simulated
// solver: a start reaches solution s with a known probability p_s (or none),
// and solution s is worth v_s. SMS's estimate — v_s times the trials until a
// new start reaches s again — has mean Σ v_s over the solutions with p_s > 0,
// whatever the p_s; truncated at M its mean is Σ v_s (1 − (1 − p_s)^M), as the
// header states. Seen failing with the count started at 0.
#include <gtest/gtest.h>

#include <cmath>
#include "core/rng.h"
#include "integrators/manifold/reciprocal_probability.h"
#include "tests/support/statistics.h"

namespace lb::test {
namespace {

struct Solutions {
  std::vector<double> p, value;  // Σ p < 1: the rest is "no solution"
  int reached(Pcg32& rng) const {
    double u = rng.next1D(), cdf = 0;
    for (size_t s = 0; s < p.size(); ++s)
      if (u < (cdf += p[s])) return int(s);
    return -1;
  }
};

// Mean and standard error of SMS's estimate over n samples.
std::pair<double, double> smsMean(const Solutions& sol, int maxTrials, int n, uint64_t seed) {
  Pcg32 rng(seed, 7);
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i) {
    int s = sol.reached(rng);
    double x = 0;
    if (s >= 0) x = sol.value[size_t(s)] * trialsUntilSuccess([&] { return sol.reached(rng) == s; }, maxTrials);
    sum += x, sum2 += x * x;
  }
  double mean = sum / n;
  return {mean, std::sqrt((sum2 / n - mean * mean) / (n - 1))};
}

TEST(ReciprocalProbability, SmsEstimateSumsEverySolutionOnce) {
  const Solutions sol{{0.5, 0.2, 0.05, 0.01}, {1.0, 2.0, 4.0, 8.0}};  // 24 % of starts reach none
  const double total = 1 + 2 + 4 + 8;
  auto [mean, error] = smsMean(sol, 1 << 20, 400000, 3);
  EXPECT_NEAR(mean, total, normalCritical(1e-4) * error) << "standard error " << error;
}

TEST(ReciprocalProbability, TruncationUndercountsAsStated) {
  const Solutions sol{{0.5, 0.2, 0.05, 0.01}, {1.0, 2.0, 4.0, 8.0}};
  const int M = 16;
  double expected = 0;
  for (size_t s = 0; s < sol.p.size(); ++s) expected += sol.value[s] * (1 - std::pow(1 - sol.p[s], M));
  auto [mean, error] = smsMean(sol, M, 400000, 5);
  EXPECT_NEAR(mean, expected, normalCritical(1e-4) * error);
  EXPECT_LT(expected, 0.5 * 15);  // the rare solutions are mostly lost at M = 16 (6.4 of 15)
}

}  // namespace
}  // namespace lb::test
