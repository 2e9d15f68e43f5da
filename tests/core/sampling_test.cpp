// χ² tests of the warps against their densities, and sampler properties.
#include <gtest/gtest.h>
#include "core/frame.h"
#include "core/sampler.h"
#include "core/sampling.h"
#include "tests/support/statistics.h"

namespace lb::test {
namespace {

constexpr double Alpha = 0.01;
constexpr int WarpTests = 5;  // Bonferroni count for this file's χ² tests

TEST(Warps, CosineHemisphereMatchesPdf) {
  SphereHistogramTest t;
  auto r = t.run([](Vec2 u, float) { return std::optional<Vec3>(sampleCosineHemisphere(u)); },
                 [](const Vec3& w) { return double(cosineHemispherePdf(w.z)); }, 1);
  EXPECT_TRUE(r.passed(Alpha / WarpTests)) << r.message << " p=" << r.pValue;
}

TEST(Warps, UniformSphereMatchesPdf) {
  SphereHistogramTest t;
  auto r = t.run([](Vec2 u, float) { return std::optional<Vec3>(sampleUniformSphere(u)); },
                 [](const Vec3&) { return double(uniformSpherePdf()); }, 2);
  EXPECT_TRUE(r.passed(Alpha / WarpTests)) << r.message << " p=" << r.pValue;
}

TEST(Warps, UniformConeMatchesPdf) {
  float cosMax = std::cos(0.6f);
  Frame f(glm::normalize(Vec3(0.3f, -0.5f, 0.8f)));
  SphereHistogramTest t;
  auto r = t.run([&](Vec2 u, float) { return std::optional<Vec3>(f.toWorld(sampleUniformCone(u, cosMax))); },
                 [&](const Vec3& w) { return f.toLocal(w).z >= cosMax ? double(uniformConePdf(cosMax)) : 0.0; }, 3);
  EXPECT_TRUE(r.passed(Alpha / WarpTests)) << r.message << " p=" << r.pValue;
}

TEST(Warps, UniformHemisphereMatchesPdf) {
  SphereHistogramTest t;
  auto r = t.run([](Vec2 u, float) { return std::optional<Vec3>(sampleUniformHemisphere(u)); },
                 [](const Vec3& w) { return w.z >= 0 ? double(uniformHemispherePdf()) : 0.0; }, 4);
  EXPECT_TRUE(r.passed(Alpha / WarpTests)) << r.message << " p=" << r.pValue;
}

// Shirley–Chiu's concentric map is uniform on the unit disc (pdf 1/π): r² and
// φ must both be uniform, which equal-area polar cells test directly.
TEST(Warps, ConcentricDiskMatchesPdf) {
  DiskHistogramTest t;
  auto r = t.run([](Vec2 u) { return std::optional<Vec2>(sampleConcentricDisk(u)); },
                 [](Vec2 p) { return glm::dot(p, p) < 1 ? double(InvPi) : 0.0; }, 6);
  EXPECT_TRUE(r.passed(Alpha / WarpTests)) << r.message << " p=" << r.pValue << " chi2=" << r.statistic;
}

TEST(Statistics, ChiSquareRejectsAWrongPdf) {
  // The harness must be able to fail: cosine samples against a uniform pdf.
  SphereHistogramTest t;
  t.samples = 100000;
  auto r = t.run([](Vec2 u, float) { return std::optional<Vec3>(sampleCosineHemisphere(u)); },
                 [](const Vec3& w) { return w.z >= 0 ? double(uniformHemispherePdf()) : 0.0; }, 5);
  EXPECT_FALSE(r.passed(Alpha));
}

// Low-expectation cells are pooled, and a pool still below 5 is merged into
// the smallest cell that passed (Nori), never dropped: 40 samples where 3 are
// expected must fail however well the big cells fit.
TEST(Statistics, ChiSquareMergesASmallPoolIntoItsNeighbour) {
  std::vector<double> expected = {1, 1, 1, 50, 60, 70, 80}, observed = {40, 0, 0, 50, 60, 70, 80};
  Chi2Result r = chi2Test(observed, expected);
  // Pool {1, 1, 1} (3 < 5) absorbs the 50 cell: observed 90 vs expected 53.
  EXPECT_NEAR(r.statistic, 37.0 * 37.0 / 53.0, 1e-9);
  EXPECT_EQ(r.dof, 3);  // cells: pool, 60, 70, 80
  EXPECT_FALSE(r.passed(Alpha));
  // A pool that reaches 5 on its own stays a cell of its own.
  r = chi2Test({3, 3, 50, 60}, {2.5, 2.5, 50, 60});
  EXPECT_NEAR(r.statistic, 1.0 * 1.0 / 5.0, 1e-12);
  EXPECT_EQ(r.dof, 2);
}

TEST(Statistics, GammaQMatchesKnownValues) {
  // χ² survival function: P(χ²_2 > 2) = e^-1, P(χ²_1 > 3.841459) = 0.05.
  EXPECT_NEAR(gammaQ(1.0, 1.0), std::exp(-1.0), 1e-12);
  EXPECT_NEAR(gammaQ(0.5, 3.841459 / 2), 0.05, 1e-6);
  EXPECT_NEAR(normalCritical(0.05), 1.959964, 1e-5);
}

TEST(DiscreteDistribution, FrequenciesMatchPmf) {
  DiscreteDistribution d({1.f, 0.f, 3.f, 6.f});
  std::vector<double> observed(4, 0), expected;
  Pcg32 rng(9, 1);
  const int n = 200000;
  for (int i = 0; i < n; ++i) observed[d.sample(rng.next1D())] += 1;
  for (size_t i = 0; i < 4; ++i) expected.push_back(d.pmf(i) * n);
  EXPECT_EQ(observed[1], 0);
  auto r = chi2Test(observed, expected);
  EXPECT_TRUE(r.passed(Alpha)) << r.message << " p=" << r.pValue;
}

TEST(Samplers, SameSeedPixelAndIndexGiveTheSameNumbers) {
  for (std::string type : {"independent", "stratified"}) {
    auto a = makeSampler({type, 4}, 42), b = makeSampler({type, 4}, 42);
    b->start(7, 3);  // touch b in another order first
    b->get2D();
    a->start(11, 5);
    b->start(11, 5);
    for (int i = 0; i < 10; ++i) EXPECT_EQ(a->get1D(), b->get1D()) << type;
  }
}

TEST(Samplers, StratifiedBlockCoversEveryStratumOnce) {
  const int n = 4;
  auto s = makeSampler({"stratified", n}, 3);
  for (int dim = 0; dim < 3; ++dim) {
    std::vector<int> hits(n * n, 0);
    for (int i = 0; i < n * n; ++i) {
      s->start(5, uint64_t(16 + i));  // second block
      for (int d = 0; d < dim; ++d) s->get2D();
      Vec2 u = s->get2D();
      hits[int(u.y * n) * n + int(u.x * n)] += 1;
    }
    for (int h : hits) EXPECT_EQ(h, 1) << "dimension " << dim;
  }
}

TEST(Samplers, StratifiedSamplesAreUniform) {
  // Marginal uniformity over many pixels (each sample must be unbiased alone),
  // for strata² a power of two and not (3² = 9 caught a permutation whose
  // first element was not uniform over keys).
  for (int strata : {4, 3}) {
    auto s = makeSampler({"stratified", strata}, 8);
    const int bins = 16, n = 160000;
    std::vector<double> observed(bins * bins, 0), expected(bins * bins, double(n) / (bins * bins));
    for (int i = 0; i < n; ++i) {
      s->start(uint64_t(i / 5), uint64_t(i % 5));
      Vec2 u = s->get2D();
      observed[size_t(int(u.y * bins) * bins + int(u.x * bins))] += 1;
    }
    auto r = chi2Test(observed, expected);
    EXPECT_TRUE(r.passed(Alpha)) << "strata " << strata << ": " << r.message << " p=" << r.pValue;
  }
}

}  // namespace
}  // namespace lb::test
