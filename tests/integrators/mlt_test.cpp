// The `mlt` integrator (issue 17): primary-sample-space MLT over the path
// tracer and over BDPT, and multiplexed MLT, against BDPT on the Cornell box
// and the glass-sphere caustic; determinism; the multiplexed strategy choice.
// The Metropolis machinery itself (kernels, acceptance, the toy integrand) is
// tested in mlt_metropolis_test.cpp.
//
// A Markov chain's passes are correlated, so the film's per-pixel variance is
// no error estimate (the film reports it as unknown): every comparison here
// averages independent runs (seeds) and takes the variance from their spread,
// with Student-t critical values (tests/support/repeats.h). Each run has its
// own bootstrap, so the error of the normalisation b is part of that spread.
#include <gtest/gtest.h>
#include <cmath>
#include "core/error.h"
#include "integrators/mlt/integrands.h"
#include "integrators/registry.h"
#include "tests/support/render_helpers.h"
#include "tests/support/repeats.h"
#include "tests/support/statistics.h"

namespace lb::test {
namespace {

constexpr double Alpha = 1e-3;

struct MltCase {
  const char* name;
  const char* params;
};
const MltCase Modes[] = {
    {"pssmlt_path", "{mode: pssmlt, base: path, bootstrap_samples: 400000, chains: 16}"},
    {"pssmlt_bdpt", "{mode: pssmlt, base: bdpt, bootstrap_samples: 200000, chains: 16}"},
    {"mmlt", "{mode: mmlt, bootstrap_samples: 400000, chains: 16}"},
};

// 12 independent runs of each MLT mode (`spp` mutations per pixel) and of
// BDPT (`bdptSpp`), region means over 2×2 regions compared by Welch t-tests (Šidák
// over regions, channels and modes). The whole image's mean is checked to be
// tight enough to catch a 5 % error, so the test can fail: an MLT image's
// mean luminance is its b̂ exactly (each mutation splats b̂ in all), so that is
// where a wrong normalisation or selection probability shows; 400000
// bootstrap samples (200000 for BDPT samples, which cost more) keep b̂'s
// error near 1 % per run on these scenes.
void expectAgreementWithBdpt(const char* scene, int w, int h, const std::string& extra, uint64_t spp,
                             uint64_t bdptSpp, std::vector<MltCase> modes) {
  const int Seeds = 12, Regions = 2;
  SceneFile sf = loadShippedScene(scene, w, h);
  SeedMeans bdpt = seedMeans(sf, {"bdpt", "{}", bdptSpp}, Seeds, Regions, Regions, 500, extra);
  for (const MltCase& m : modes) {
    SeedMeans mlt = seedMeans(sf, {"mlt", m.params, spp}, Seeds, Regions, Regions, 900, extra);
    EXPECT_EQ(mlt.nonFinite, 0u) << m.name;
    std::string failures = compareSeedMeans(mlt, bdpt, Alpha, Regions * Regions * 3 * int(modes.size()));
    EXPECT_TRUE(failures.empty()) << scene << ", " << m.name << ":" << failures;
    // The whole image's mean luminance, from each seed's (regions and
    // channels are correlated through b̂, so their variances do not add):
    // agreement, and power, i.e. a 5 % error would exceed the bound with
    // probability 0.9 (bound + z₀.₉·σ ≤ 5 %).
    const RunningStats& a = mlt.imageLuminance;
    const RunningStats& r = bdpt.imageLuminance;
    double se = std::sqrt(a.varianceOfMean() + r.varianceOfMean());
    double bound = studentCritical(sidak(Alpha, int(modes.size())), Seeds - 1) * se;
    double power = bound + normalCritical(0.2) * se;
    std::cout << scene << " " << m.name << ": mean luminance " << a.mean << " vs BDPT " << r.mean << ", bound ±"
              << bound << " (" << 100 * bound / r.mean << " %); standard errors: mlt "
              << std::sqrt(a.varianceOfMean()) << ", bdpt " << std::sqrt(r.varianceOfMean()) << "\n";
    EXPECT_LE(std::abs(a.mean - r.mean), bound) << scene << ", " << m.name;
    EXPECT_LE(power, 0.05 * r.mean) << scene << ", " << m.name << ": too noisy to catch a 5 % error";
  }
}

TEST(Mlt, AgreesWithBdptOnTheCornellBox) {
  expectAgreementWithBdpt("cornell-box", 16, 16, "{}", 256, 1024, {std::begin(Modes), std::end(Modes)});
}

// The caustic at max_depth 4, the length that carries it (camera, floor,
// glass, glass, light). Beyond it, paths such as camera-floor-glass-glass-
// glass-light are found only by hitting the small light (s = 0) and are so
// rare and so bright that no mean of a few million samples is normally
// distributed: BDPT's (s=0, t=6) image at 16384 spp is a handful of fireflies
// that add 1.7 % to the image, which multiplexed MLT's 2 M bootstrap samples
// did not meet at all. And the path tracer finds the length-4 caustic itself
// only by hitting the light through the glass, the same heavy tail, so
// pssmlt over `path` is compared on the Cornell box only.
TEST(Mlt, AgreesWithBdptOnTheGlassSphereCaustic) {
  expectAgreementWithBdpt("caustic-glass-sphere", 16, 12, "{max_depth: 4}", 1024, 1024, {Modes[1], Modes[2]});
}

// The image depends on the seed only: the chains are a fixed number, each
// with its own streams and share of every pass, splatted in chain order.
TEST(Mlt, SameSeedGivesTheSameImageWithOneAndTwoThreads) {
  SceneFile sf = loadShippedScene("caustic-glass-sphere", 16, 12);
  for (const MltCase& m : Modes) {
    Image one = renderScene(sf, {"mlt", m.params, 8, 3, 1})->image();
    Image two = renderScene(sf, {"mlt", m.params, 8, 3, 2})->image();
    Image other = renderScene(sf, {"mlt", m.params, 8, 4, 2})->image();
    EXPECT_EQ(one.pixels, two.pixels) << m.name;
    EXPECT_NE(one.pixels, other.pixels) << m.name << ": another seed should give another image";
  }
}

// Passes of a chain are correlated: the film must not report their spread as
// the error.
TEST(Mlt, FilmVarianceIsReportedUnknown) {
  SceneFile sf = loadShippedScene("cornell-box", 8, 8);
  auto film = renderScene(sf, {"mlt", "{bootstrap_samples: 1000, chains: 4}", 4, 1});
  EXPECT_TRUE(std::isnan(film->meanVarianceOfMean()));
  auto path = renderScene(sf, {"path", "{}", 4, 1});
  EXPECT_FALSE(std::isnan(path->meanVarianceOfMean()));
}

// Multiplexed MLT's control numbers choose length k with probability p(k)
// (uniform, or set from the pilot) and then one of its strategies uniformly;
// choose() must hit each (k, s) with the probability it reports, which
// divides the contribution.
void expectChoicesFollow(const mlt::MultiplexedIntegrand& integrand, int K,
                         const std::function<double(int)>& pLength, const char* label) {
  std::vector<std::pair<int, int>> cells;
  for (int k = 1; k <= K; ++k)
    for (int s = 0; s <= k; ++s)
      if (!(k == 1 && s == 1)) cells.push_back({k, s});
  std::vector<double> observed(cells.size(), 0), expected;
  const int N = 200000;
  Pcg32 rng(7, 1);
  for (int i = 0; i < N; ++i) {
    auto c = integrand.choose(rng.next1D(), rng.next1D());
    ASSERT_EQ(c.s + c.t - 1, c.k);
    ASSERT_GE(c.t, 1);
    ASSERT_FALSE(c.s == 1 && c.t == 1);
    size_t cell = size_t(std::find(cells.begin(), cells.end(), std::make_pair(c.k, c.s)) - cells.begin());
    ASSERT_LT(cell, cells.size());
    observed[cell] += 1;
    // The probability it reports, from the definition (float rounding of the
    // CDF's differences only).
    double p = pLength(c.k) / (c.k == 1 ? 1 : c.k + 1);
    ASSERT_NEAR(c.probability, p, 1e-5 * p) << label;
  }
  for (auto [k, s] : cells) expected.push_back(double(N) * pLength(k) / (k == 1 ? 1 : k + 1));
  Chi2Result r = chi2Test(observed, expected);
  EXPECT_TRUE(r.passed(sidak(Alpha, 2))) << label << ": " << r.message << " p = " << r.pValue;
}

TEST(Mlt, MultiplexedChoiceMatchesItsProbability) {
  const int K = 6;
  SceneFile sf = loadShippedScene("cornell-box", 4, 4);
  mlt::MultiplexedIntegrand integrand(*sf.scene, K, bidir::MisWeighting::Power);
  expectChoicesFollow(integrand, K, [&](int) { return 1.0 / K; }, "uniform lengths");
  const std::vector<double> weights = {0.05, 3, 1, 0.5, 0.25, 0.2};  // normalised by the integrand
  integrand.setLengthProbabilities(weights);
  double total = 0;
  for (double w : weights) total += w;
  expectChoicesFollow(integrand, K, [&](int k) { return weights[size_t(k - 1)] / total; }, "pilot lengths");
}

TEST(Mlt, RefusesKeysItWouldIgnoreAndLengthsItCannotChoose) {
  YAML::Node node = YAML::Load("{mode: mmlt, max_depth: -1}");
  Params p(node, "x.yaml", "integrator");
  try {
    makeIntegrator("mlt", p, "x.yaml", 1);
    FAIL() << "accepted max_depth -1 with mode mmlt";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("max_depth"), std::string::npos) << e.what();
  }
  // base belongs to pssmlt, mis to BDPT's strategies; a length of 0 has none.
  for (const char* yaml : {"{mode: mmlt, base: bdpt}", "{mode: mmlt, max_depth: 0}",
                           "{mode: pssmlt, base: path, mis: balance}"}) {
    YAML::Node node = YAML::Load(yaml);
    Params q(node, "x.yaml", "integrator");
    EXPECT_THROW(makeIntegrator("mlt", q, "x.yaml", 1), ConfigError) << yaml;
  }
}

}  // namespace
}  // namespace lb::test
