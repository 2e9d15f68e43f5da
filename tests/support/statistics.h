#pragma once
// Statistical tools for the tests (testing.md §1–3). Every tolerance in the
// suite comes from these: a significance level and a measured variance or a
// sample count, never a hand-picked epsilon.
#include <functional>
#include <optional>
#include <string>
#include <vector>
#include "core/frame.h"

namespace lb::test {

// Regularised upper incomplete gamma Q(a, x) (Numerical Recipes §6.2 method).
double gammaQ(double a, double x);
// Two-sided standard normal critical value for significance alpha.
double normalCritical(double alphaTwoSided);
// Two-sided Student-t critical value with `dof` degrees of freedom (for means
// whose variance is estimated from a few independent repeats).
double studentCritical(double alphaTwoSided, double dof);
// Per-test level such that `count` independent tests all pass with probability 1 - alpha.
inline double sidak(double alpha, int count) { return 1 - std::pow(1 - alpha, 1.0 / count); }

struct Chi2Result {
  double statistic = 0, pValue = 1;
  int dof = 0;
  std::string message;  // why it failed, if it did
  bool passed(double alpha) const { return message.empty() && pValue >= alpha; }
};

// Pearson's χ² test; cells with expected count < minExpected are pooled, and
// a pool still below minExpected is merged into the smallest cell that passed
// (Nori's chi2test). A sample in a cell of zero expected count fails outright.
Chi2Result chi2Test(const std::vector<double>& observed, const std::vector<double>& expected, double minExpected = 5);

// Histogram of directions over the sphere in (θ, φ) cells, and the expected counts from integrating `pdf` over each cell
// (composite Simpson on a sub-grid). Directions from `sample` may be absent
// (failed sample); those are counted and must match the missing pdf mass.
struct SphereHistogramTest {
  int thetaCells = 24, phiCells = 48;
  size_t samples = 1000000;
  // Optional zoom: cells cover only the cap cosθ >= zMin around frame.n, so
  // small lights and narrow lobes spread over many cells. Samples outside the
  // cap fall in one extra cell whose expected mass is 1 - ∫_cap pdf.
  Frame frame;
  double zMin = -1;
  using SampleFn = std::function<std::optional<Vec3>(Vec2 u, float uLobe)>;
  using PdfFn = std::function<double(const Vec3&)>;
  Chi2Result run(const SampleFn& sample, const PdfFn& pdf, uint64_t seed) const;
  // The two halves, so one set of expected counts can serve several samplers.
  std::vector<double> expectedCounts(const PdfFn& pdf) const;
  std::vector<double> observedCounts(const SampleFn& sample, uint64_t seed) const;
  // χ², after re-integrating (deeper) any cell that has samples but no mass.
  Chi2Result compare(const std::vector<double>& observed, std::vector<double> expected, const PdfFn& pdf) const;

 private:
  int cellOf(const Vec3& world) const;
  double thetaMax() const;
  double cellIntegral(const PdfFn& pdf, int cell, int depth, int minDepth = 2) const;
};

// Points in the unit disc, histogrammed in equal-area polar cells (r² and φ
// uniform), against `pdf` (a density per unit area of the disc) integrated
// over each cell. Points outside the disc, or failed samples, fall in one
// extra cell whose expected mass is 1 − ∫_disc pdf.
struct DiskHistogramTest {
  int radialCells = 16, phiCells = 32;
  size_t samples = 300000;
  using SampleFn = std::function<std::optional<Vec2>(Vec2 u)>;
  using PdfFn = std::function<double(Vec2)>;
  Chi2Result run(const SampleFn& sample, const PdfFn& pdf, uint64_t seed) const;
};

// ∫ f dω over the whole sphere for up to three channels at once (e.g. RGB),
// by adaptive Gauss–Legendre product rules on θ×φ cells around frame.n: a
// cell is split until its 4×4 and 8×8 rules differ by less than its share (by
// parameter area) of `absTolerance` in every channel. `error` sums those
// differences over the final cells: an estimate of the coarser rule's error,
// so an over-estimate of the finer one's (which is summed) once the starting
// cells resolve the integrand's features.
struct SphereIntegral {
  glm::dvec3 value{0.0}, error{0.0};
};
SphereIntegral integrateSphere(const std::function<glm::dvec3(const Vec3&)>& f, double absTolerance,
                               int thetaCells = 16, int phiCells = 32, const Frame& frame = Frame(), int maxDepth = 7);

// z statistic for the difference of two means with known standard errors.
inline double zScore(double meanA, double varMeanA, double meanB, double varMeanB) {
  double s = std::sqrt(varMeanA + varMeanB);
  return s > 0 ? (meanA - meanB) / s : (meanA == meanB ? 0 : INFINITY);
}

// Running mean and variance (Welford).
struct RunningStats {
  double n = 0, mean = 0, m2 = 0;
  void add(double x) {
    n += 1;
    double d = x - mean;
    mean += d / n;
    m2 += d * (x - mean);
  }
  double variance() const { return n > 1 ? m2 / (n - 1) : 0; }
  double varianceOfMean() const { return n > 1 ? variance() / n : 0; }
};

}  // namespace lb::test
