// The Metropolis estimator of `mlt` (integrators/mlt/metropolis.h) on a toy
// 2-D integrand whose pixel integrals are known: bootstrap normalisation,
// chains started in proportion to f, expected-value splats, over 16 seeds.
// References: Kelemen, Szirmay-Kalos, Antal, Csonka 2002 (§5 the estimator);
// Veach 1997, ch. 11 (expected-value splatting §11.3.4, start-up bias §11.3.3).
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>
#include "core/rng.h"
#include "integrators/mlt/metropolis.h"
#include "tests/support/statistics.h"

namespace lb::test {
namespace {

constexpr double Alpha = 1e-3;

// A toy target with known pixel values: g(u, v) = (0.2 + u²)(1 + ½ sin 2πv)
// plus 3 on the disc of radius 0.1 around (0.625, 0.3) (a small bright feature,
// where MLT concentrates its mutations), splatted at raster (4u, v): four
// pixels, the columns [j/4, (j + 1)/4) of the unit square. The disc lies
// inside column 2 (u ∈ [0.525, 0.725], v ∈ [0.2, 0.4]).
class ToyIntegrand final : public mlt::PrimarySpaceIntegrand {
 public:
  static constexpr int Pixels = 4;
  int streams() const override { return 1; }
  void evaluate(mlt::PrimarySampleVector& u, std::vector<mlt::Contribution>& out, uint64_t& rays) const override {
    float a = u.get(0, 0), b = u.get(0, 1);
    out.push_back({Vec2(a * float(Pixels), b), Color(float(g(a, b)))});  // grey: f = luminance = g
    ++rays;
  }
  static double g(double u, double v) {
    const double pi = std::acos(-1.0);
    double disc = (u - 0.625) * (u - 0.625) + (v - 0.3) * (v - 0.3) < 0.01 ? 3 : 0;
    return (0.2 + u * u) * (1 + 0.5 * std::sin(2 * pi * v)) + disc;
  }
  // Pixel j's value is P·∫ over its column (metropolis.h: I_j = P ∫ h_j du):
  // ∫₀¹ (1 + ½ sin 2πv) dv = 1, ∫ (0.2 + u²) du over the column is
  // 0.2/4 + ((j + 1)³ − j³)/(3·4³), and the disc adds 3·π·0.1² to column 2.
  static double pixelValue(int j) {
    const double pi = std::acos(-1.0);
    double column = 0.2 / Pixels + (std::pow(j + 1.0, 3) - std::pow(double(j), 3)) / (3 * std::pow(double(Pixels), 3));
    return Pixels * (column + (j == 2 ? 3 * pi * 0.01 : 0));
  }
};

// One run as the integrator does it (mlt.cpp): a bootstrap of `bootstrapSamples`,
// `chains` chains started in proportion to f among them, each `mutations`
// long, splats with scale P·b̂/N (N: all chains' mutations) summed per pixel.
std::array<double, ToyIntegrand::Pixels> toyEstimate(uint64_t seed, uint64_t bootstrapSamples, uint64_t mutations,
                                                     int chains) {
  ToyIntegrand toy;
  mlt::MetropolisSettings settings;
  uint64_t rays = 0;
  mlt::Bootstrap bootstrap = mlt::runBootstrap(toy, settings, seed, bootstrapSamples, rays);
  const double scale = ToyIntegrand::Pixels * bootstrap.b / double(uint64_t(chains) * mutations);
  std::array<double, ToyIntegrand::Pixels> pixel{};
  Pcg32 pick(hashValues(seed, 0x57a27), 0);
  std::vector<Splat> splats;
  std::vector<Vec2> nonFinite;
  for (int c = 0; c < chains; ++c) {
    mlt::MarkovChain chain(toy, settings, seed, bootstrap.choose(pick.next1D()), uint64_t(c), rays);
    splats.clear();
    chain.run(mutations, scale, splats, nonFinite, rays);
    for (const Splat& s : splats) pixel[size_t(std::clamp(int(s.raster.x), 0, ToyIntegrand::Pixels - 1))] += s.value.r;
  }
  EXPECT_TRUE(nonFinite.empty());
  return pixel;
}

// P(F ≤ f) for F ~ F(ν, ν) with ν even: I_x(ν/2, ν/2) at x = f/(1 + f), which
// for integer parameters is the binomial tail P(Bin(ν − 1, x) ≥ ν/2).
double fCdfEqualEvenDof(double f, int nu) {
  const double x = f / (1 + f);
  const int n = nu - 1;
  double sum = 0;
  for (int k = nu / 2; k <= n; ++k)
    sum += std::exp(std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0) + k * std::log(x) +
                    (n - k) * std::log1p(-x));
  return sum;
}
double fQuantileEqualEvenDof(double p, int nu) {
  double lo = 0, hi = 1;
  while (fCdfEqualEvenDof(hi, nu) < p) hi *= 2;
  for (int i = 0; i < 200; ++i) {
    double mid = 0.5 * (lo + hi);
    (fCdfEqualEvenDof(mid, nu) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// The toy test: the Metropolis estimate with bootstrap normalisation
// converges to the known pixel values (Kelemen et al. §5; Veach 1997 §11.3),
// over S = 16 seeds at two sizes, the second with 16× the bootstrap samples
// and 16× the mutations (so both parts of the error shrink alike).
//  (a) each pixel's mean over seeds is within t_{S−1}·sd/√S of its value
//      (Student-t, Šidák over 4 pixels × 2 sizes): no bias beyond noise, at
//      the larger size too, where start-up bias would show first;
//  (b) the error falls at MCMC's 1/√N rate: the RMS error ratio between the
//      sizes is ¼ in expectation. Each seed's squared error Σ_j e_j² is a sum
//      of squares of (by the CLT over many mutations) Gaussian errors, a
//      weighted χ² with at least one effective degree of freedom (the four
//      pixels' errors are correlated: their sum is P·b̂'s error), so
//      conservatively each mean over seeds is σ²·χ²_S/S and the ratio of the
//      two mean squares is (1/16)·F(S, S): the RMS ratio must stay below
//      ¼·√F_{1−α}(S, S). An estimator whose error did not fall (ratio ≈ 1),
//      e.g. a chain stuck in its start or a wrong scale per pass, fails it.
TEST(MltMetropolis, ToyIntegrandConverges) {
  const int Seeds = 16, Chains = 8, P = ToyIntegrand::Pixels;
  struct Size {
    uint64_t bootstrap, mutations;
  };
  const Size sizes[] = {{10000, 1000}, {160000, 16000}};
  const double t = studentCritical(sidak(Alpha, 2 * P), Seeds - 1);
  double meanSquare[2] = {0, 0};
  for (int s = 0; s < 2; ++s) {
    std::array<RunningStats, ToyIntegrand::Pixels> stats;
    for (int seed = 0; seed < Seeds; ++seed) {
      auto pixel = toyEstimate(hashValues(0x70f, s, seed), sizes[s].bootstrap, sizes[s].mutations, Chains);
      for (int j = 0; j < P; ++j) {
        stats[size_t(j)].add(pixel[size_t(j)]);
        meanSquare[s] += std::pow(pixel[size_t(j)] - ToyIntegrand::pixelValue(j), 2) / Seeds;
      }
    }
    for (int j = 0; j < P; ++j) {
      const RunningStats& st = stats[size_t(j)];
      double exact = ToyIntegrand::pixelValue(j), bound = t * std::sqrt(st.varianceOfMean());
      std::cout << Chains << " chains × " << sizes[s].mutations << " mutations, " << sizes[s].bootstrap
                << " bootstrap samples: pixel " << j << " mean " << st.mean << " vs exact " << exact << ", |error| "
                << std::abs(st.mean - exact) << " ≤ " << bound << " (sd over seeds " << std::sqrt(st.variance())
                << ")\n";
      EXPECT_LE(std::abs(st.mean - exact), bound) << "pixel " << j << ", size " << s;
    }
  }
  double ratio = std::sqrt(meanSquare[1] / meanSquare[0]);
  double bound = 0.25 * std::sqrt(fQuantileEqualEvenDof(1 - Alpha, Seeds));
  std::cout << "root mean (over seeds) squared error norm over the pixels " << std::sqrt(meanSquare[0]) << " → "
            << std::sqrt(meanSquare[1])
            << " with 16× the samples: ratio " << ratio << " (1/√16 = 0.25 expected, bound " << bound << ")\n";
  EXPECT_LT(ratio, bound);
}


}  // namespace
}  // namespace lb::test
