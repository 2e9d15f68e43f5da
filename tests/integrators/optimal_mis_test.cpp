// Optimal MIS's arithmetic (integrators/direct_optimal/optimal_mis.h) on a
// one-dimensional integrand whose densities and integrals are known:
// f(x) = 3x² on [0, 1] (∫ f = 1), technique 0 uniform, technique 1 the
// density 2x. Against the definition, computed another way:
//  * the estimator is unbiased for any α, including absurd ones, and also
//    when a technique sometimes produces no sample (where the paper's
//    constant Σ α_i would be biased by Σ α_i (1 − m_i));
//  * the α the running sums solve for converges to the α of the system
//    A α = b with A and b integrated by quadrature from their definitions;
//  * that α is where the estimator's variance is smallest, found by
//    measuring the variance itself (no linear system) along the one
//    direction in which α changes the estimate;
//  * the solver leaves a residual within rounding.
#include <gtest/gtest.h>
#include <cmath>
#include <random>
#include <vector>
#include "integrators/direct_optimal/optimal_mis.h"

namespace lb {
namespace {

double integrand(double x) { return 3 * x * x; }

// Technique 0 produces a sample with probability m0 (uniform on [0, 1], so
// its density is m0); technique 1 always (density 2x).
struct ToyTechniques {
  double m0 = 1;
  double p0(double) const { return m0; }
  static double p1(double x) { return 2 * x; }
  OmisSample at(double x) const { return OmisSample{Color(float(integrand(x))), {float(p0(x)), float(p1(x))}}; }
};

struct Round {
  OmisSample samples[OmisTechniques];
  int count = 0;
  std::array<bool, OmisTechniques> produced{false, false};
};

Round drawRound(const ToyTechniques& t, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  Round r;
  if (u(rng) < t.m0) r.produced[0] = true, r.samples[r.count++] = t.at(u(rng));
  double x = std::sqrt(u(rng));
  if (x > 0) r.produced[1] = true, r.samples[r.count++] = t.at(x);
  return r;
}

// A and b by the midpoint rule, from their definitions.
struct System {
  double A[2][2] = {{0, 0}, {0, 0}}, b[2] = {0, 0};
  double alpha[2] = {0, 0};
};
System systemByQuadrature(const ToyTechniques& t) {
  System s;
  const int n = 1 << 20;
  for (int i = 0; i < n; ++i) {
    double x = (i + 0.5) / n, p[2] = {t.p0(x), t.p1(x)}, S = p[0] + p[1];
    for (int a = 0; a < 2; ++a) {
      s.b[a] += integrand(x) * p[a] / S / n;
      for (int c = 0; c < 2; ++c) s.A[a][c] += p[a] * p[c] / S / n;
    }
  }
  double det = s.A[0][0] * s.A[1][1] - s.A[0][1] * s.A[1][0];
  s.alpha[0] = (s.A[1][1] * s.b[0] - s.A[0][1] * s.b[1]) / det;
  s.alpha[1] = (s.A[0][0] * s.b[1] - s.A[1][0] * s.b[0]) / det;
  return s;
}

OmisAlpha constantAlpha(double a0, double a1) { return {glm::dvec3(a0), glm::dvec3(a1)}; }

TEST(OptimalMis, EstimatorIsUnbiasedForAnyCoefficients) {
  for (double m0 : {1.0, 0.8}) {
    ToyTechniques t{m0};
    for (OmisAlpha alpha : {constantAlpha(0, 0), constantAlpha(5, -3), constantAlpha(-2, 7)}) {
      std::mt19937_64 rng(11);
      const int n = 400000;
      double sum = 0, squares = 0;
      for (int i = 0; i < n; ++i) {
        Round r = drawRound(t, rng);
        double F = optimalMisEstimate(alpha, r.samples, r.count, r.produced).x;
        sum += F, squares += F * F;
      }
      double mean = sum / n, standardError = std::sqrt((squares / n - mean * mean) / n);
      // Six estimates, each two-sided at 1e-4 (z = 3.9).
      EXPECT_LT(std::abs(mean - 1.0), 3.9 * standardError)
          << "m0 " << m0 << ", alpha (" << alpha[0].x << ", " << alpha[1].x << "): mean " << mean;
    }
  }
}

// The pooled sums' α against the quadrature's, the error of the pooled α
// from the spread of batch α's (its bias, O(1/n), is far below it).
TEST(OptimalMis, LearnedCoefficientsSolveTheSystemOfTheDefinition) {
  for (double m0 : {1.0, 0.8}) {
    ToyTechniques t{m0};
    System exact = systemByQuadrature(t);
    std::mt19937_64 rng(5);
    const int batches = 40, perBatch = 20000;
    OptimalMisSums pooled;
    std::vector<double> batchAlpha[2];
    for (int k = 0; k < batches; ++k) {
      OptimalMisSums batch;
      for (int i = 0; i < perBatch; ++i) {
        Round r = drawRound(t, rng);
        for (int j = 0; j < r.count; ++j) batch.record(r.samples[j]), pooled.record(r.samples[j]);
      }
      OmisAlpha a = batch.solve();
      for (int c = 0; c < 2; ++c) batchAlpha[c].push_back(a[c].x);
    }
    OmisAlpha alpha = pooled.solve();
    for (int c = 0; c < 2; ++c) {
      double mean = 0, var = 0;
      for (double a : batchAlpha[c]) mean += a / batches;
      for (double a : batchAlpha[c]) var += (a - mean) * (a - mean) / (batches - 1);
      double standardError = std::sqrt(var / batches);
      EXPECT_LT(std::abs(alpha[c].x - exact.alpha[c]), 4 * standardError)
          << "m0 " << m0 << ", alpha_" << c << ": learned " << alpha[c].x << ", quadrature " << exact.alpha[c];
      // The solver itself: Â α − b̂ within rounding of b̂.
      glm::dvec2 r = pooled.residual(alpha, 0);
      EXPECT_LT(std::abs(r[c]), 1e-12 * std::abs(pooled.b(c).x)) << c;
    }
    // The paper's system differs from the balance heuristic's α = 0 here,
    // so the comparisons above are not of zeros.
    EXPECT_GT(std::abs(exact.alpha[0] - exact.alpha[1]), 0.05);
  }
}

// The variance of F(α), measured on one set of rounds, is a quadratic in α.
// α only matters along (1, −1) (adding t to both changes F by
// t (s_0 + s_1 − count) = 0), so the empirical variance along
// α* + τ (1, −1) is a parabola in τ; its vertex, τ̂, must be 0 within its
// spread over batches if the system's α* is the minimum-variance one.
TEST(OptimalMis, SystemsCoefficientsMinimiseTheMeasuredVariance) {
  ToyTechniques t{1.0};
  System exact = systemByQuadrature(t);
  std::mt19937_64 rng(9);
  const int batches = 40, perBatch = 20000;
  std::vector<double> vertex;
  for (int k = 0; k < batches; ++k) {
    // F(τ) = F(α*) + τ G with G = F(α* + (1, −1)) − F(α*): Var = V_F + 2τ C + τ² V_G.
    double sF = 0, sG = 0, sFF = 0, sFG = 0, sGG = 0;
    OmisAlpha star = constantAlpha(exact.alpha[0], exact.alpha[1]);
    OmisAlpha moved = constantAlpha(exact.alpha[0] + 1, exact.alpha[1] - 1);
    for (int i = 0; i < perBatch; ++i) {
      Round r = drawRound(t, rng);
      double F = optimalMisEstimate(star, r.samples, r.count, r.produced).x;
      double G = optimalMisEstimate(moved, r.samples, r.count, r.produced).x - F;
      sF += F, sG += G, sFF += F * F, sFG += F * G, sGG += G * G;
    }
    double n = perBatch, covariance = sFG / n - sF / n * sG / n, varianceG = sGG / n - sG / n * sG / n;
    vertex.push_back(-covariance / varianceG);
  }
  double mean = 0, var = 0;
  for (double v : vertex) mean += v / batches;
  for (double v : vertex) var += (v - mean) * (v - mean) / (batches - 1);
  EXPECT_LT(std::abs(mean), 4 * std::sqrt(var / batches)) << "the variance is smallest at tau = " << mean;
  // And the balance heuristic (α = 0) is measurably worse: not at the vertex.
  EXPECT_GT(std::abs(exact.alpha[0] - exact.alpha[1]) / 2, 10 * std::sqrt(var / batches));
}

TEST(OptimalMis, SingularSystemFallsBackToTheBalanceHeuristic) {
  OptimalMisSums sums;
  EXPECT_EQ(sums.solve()[0], glm::dvec3(0));  // nothing recorded
  // Proportional densities at every sample: A is singular.
  sums.record(OmisSample{Color(1.f), {1.f, 2.f}});
  sums.record(OmisSample{Color(3.f), {2.f, 4.f}});
  OmisAlpha a = sums.solve();
  EXPECT_EQ(a[0], glm::dvec3(0));
  EXPECT_EQ(a[1], glm::dvec3(0));
}

}  // namespace
}  // namespace lb
