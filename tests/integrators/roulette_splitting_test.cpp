// Learned Russian roulette and splitting (integrators/path_estimator/
// roulette_splitting.h, path_splitting.cpp):
//  * ADRRS's window and EARS's factor against the papers' rules, written out
//    case by case here;
//  * the cache's statistics against the definitions (mean, second moment,
//    variance, cost), exact whatever the order and the thread that recorded
//    them, with a sparse bin falling back to its cell;
//  * the pixel estimates: a 3 × 3 box of the passes' means, and EARS's
//    image factor sqrt(C / E) with E's largest errors left out;
//  * the estimator is unbiased under a deliberately wrong cache the test
//    controls (splitting 20-fold in some cells, roulette at 0.05 in others):
//    the furnace's analytic L = 2 and the Cornell box against classic roulette;
//  * the image does not depend on the thread count; refusals.
// (The learned caches of real renders are checked against classic roulette
// on three scenes in path_variants_test.cpp.)
#include <gtest/gtest.h>
#include <tbb/parallel_for.h>
#include <cmath>
#include <cstring>
#include <random>
#include "integrators/integrator.h"
#include "integrators/path_estimator/path_estimator.h"
#include "tests/support/render_helpers.h"

namespace lb::test {
namespace {

float meanOf(const Color& c) { return (c.r + c.g + c.b) / 3; }

TEST(RouletteSplitting, AdrrsKeepsTheContributionInsideItsWindow) {
  // s = 5: the window around the pixel estimate is [2/(1+s), 2s/(1+s)] = [1/3, 5/3].
  const float low = 2.f / 6.f, high = 10.f / 6.f;
  const Color mean(0.2f, 0.4f, 0.6f);  // avg_c(w · mean) = 0.4 w for a grey w
  for (float w : {0.01f, 0.5f, 0.8f, 1.f, 4.f, 4.2f, 40.f, 1000.f}) {
    float x = 0.4f * w;
    float expected = x < low ? x / low : x > high ? x / high : 1.f;
    EXPECT_NEAR(adrrsFactor(Color(w), mean), expected, 1e-5f * expected) << w;
  }
  // Per channel: w = (30, 0, 0) sees only the red mean.
  EXPECT_NEAR(adrrsFactor(Color(30, 0, 0), mean), (30 * 0.2f / 3) / high, 1e-5f);
  // Nothing known (a zero mean): no decision.
  EXPECT_EQ(adrrsFactor(Color(5.f), Color(0.f)), 1.f);
  EXPECT_EQ(clampSplitFactor(1e6f), 20.f);
  EXPECT_EQ(clampSplitFactor(1e-6f), 0.05f);
  EXPECT_EQ(clampSplitFactor(0.f), 0.05f);
}

TEST(RouletteSplitting, EarsTakesSecondMomentForRouletteAndVarianceForSplitting) {
  ContinuationStats s;
  s.secondMoment = Color(4, 1, 1);
  s.variance = Color(1, 0.25f, 0.25f);
  s.cost = 2;
  auto R = [&](float w, float image) { return std::sqrt(meanOf(w * w * s.secondMoment / s.cost)) * image; };
  auto S = [&](float w, float image) { return std::sqrt(meanOf(w * w * s.variance / s.cost)) * image; };
  // R ≤ 1: roulette by R.
  EXPECT_NEAR(earsFactor(Color(0.3f), s, 1.f), R(0.3f, 1), 1e-6f);
  ASSERT_LT(R(0.3f, 1), 1.f);
  // R > 1 but S < 1: neither.
  ASSERT_GT(R(1.5f, 1), 1.f);
  ASSERT_LT(S(1.5f, 1), 1.f);
  EXPECT_EQ(earsFactor(Color(1.5f), s, 1.f), 1.f);
  // Both above 1: split by S.
  ASSERT_GT(S(3.f, 2), 1.f);
  EXPECT_NEAR(earsFactor(Color(3.f), s, 2.f), S(3, 2), 1e-5f * S(3, 2));
  // No cost or no image error known: no decision.
  ContinuationStats free = s;
  free.cost = 0;
  EXPECT_EQ(earsFactor(Color(3.f), free, 2.f), 1.f);
  EXPECT_EQ(earsFactor(Color(3.f), s, 0.f), 1.f);
}

// A unit box split into cells of 1/2 (2 per side, 8 cells × 16 bins).
ContinuationCache unitBoxCache(int minSamples) {
  Bounds3 box;
  box.lo = Vec3(0.f);
  box.hi = Vec3(1.f);
  return ContinuationCache(box, 2, minSamples);
}

TEST(RouletteSplitting, CacheStatisticsFollowTheirDefinitionsInAnyOrder) {
  std::mt19937 rng(11);
  std::exponential_distribution<float> value(2.f);
  const Vec3 p(0.2f, 0.3f, 0.7f), up(0, 0, 1), down(0, 0, -1);
  std::vector<Color> L(300);
  std::vector<double> cost(L.size());
  for (size_t i = 0; i < L.size(); ++i) L[i] = Color(value(rng), value(rng), 0.f), cost[i] = double(1 + i % 7);

  // One cache records in order on this thread; another in reverse, spread
  // over TBB's threads (each its own sums).
  ContinuationCache inOrder = unitBoxCache(10), shuffled = unitBoxCache(10);
  const size_t slot = inOrder.slot(p, up);
  ContinuationCache::Sums* sums = inOrder.threadSums();
  for (size_t i = 0; i < L.size(); ++i) inOrder.record(sums, slot, L[i], cost[i]);
  tbb::parallel_for(size_t(0), L.size(), [&](size_t k) {
    size_t i = L.size() - 1 - k;
    shuffled.record(shuffled.threadSums(), slot, L[i], cost[i]);
  });
  inOrder.update();
  shuffled.update();
  const ContinuationStats* a = inOrder.lookup(slot);
  const ContinuationStats* b = shuffled.lookup(slot);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(std::memcmp(a, b, sizeof(ContinuationStats)), 0);  // bit for bit

  for (int c = 0; c < 3; ++c) {
    double mean = 0, moment = 0, variance = 0;
    for (const Color& l : L) mean += l[c], moment += double(l[c]) * l[c];
    mean /= double(L.size()), moment /= double(L.size());
    for (const Color& l : L) variance += (l[c] - mean) * (l[c] - mean);
    variance /= double(L.size());
    EXPECT_NEAR(a->mean[c], mean, 1e-6 * (mean + 1e-30)) << c;
    EXPECT_NEAR(a->secondMoment[c], moment, 1e-6 * (moment + 1e-30)) << c;
    EXPECT_NEAR(a->variance[c], variance, 1e-5 * (variance + 1e-30)) << c;
  }
  double meanCost = 0;
  for (double k : cost) meanCost += k;
  EXPECT_NEAR(a->cost, meanCost / double(cost.size()), 1e-6);

  // The bin of the rays arriving downwards holds nothing: it falls back to
  // its cell's total (which the up bin fills). Another cell knows nothing.
  const ContinuationStats* fallback = inOrder.lookup(inOrder.slot(p, down));
  ASSERT_TRUE(fallback);
  EXPECT_EQ(fallback->mean, a->mean);
  EXPECT_EQ(inOrder.lookup(inOrder.slot(Vec3(0.9f), up)), nullptr);
  // Below min_samples, a bin is unknown until more arrive (after update()).
  ContinuationCache sparse = unitBoxCache(400);
  for (size_t i = 0; i < L.size(); ++i) sparse.record(sparse.threadSums(), slot, L[i], cost[i]);
  sparse.update();
  EXPECT_EQ(sparse.lookup(slot), nullptr);
  for (size_t i = 0; i < L.size(); ++i) sparse.record(sparse.threadSums(), slot, L[i], cost[i]);
  EXPECT_EQ(sparse.lookup(slot), nullptr);
  sparse.update();
  EXPECT_NE(sparse.lookup(slot), nullptr);
}

TEST(RouletteSplitting, PixelEstimatesAreBoxMeansAndTheImageFactorItsDefinition) {
  const int W = 4, H = 3;
  PixelEstimates pixels(W, H);
  EXPECT_EQ(pixels.estimate(1, 1), Color(0.5f));  // before any pass
  auto value = [](int x, int y, int pass) { return Color(float(x + 2 * y + pass), 1.f, 0.5f * float(x)); };
  auto rays = [](int x, int y) { return double(3 + x + y); };
  for (int pass = 0; pass < 2; ++pass) {
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) pixels.record(x, y, value(x, y, pass), rays(x, y));
    // E and C of this pass, against the estimates it was recorded with.
    std::vector<double> errors;
    double error = 0, cost = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        Color P = pixels.estimate(x, y);
        Color e = (value(x, y, pass) - P) / (P + Color(0.01f));
        error += meanOf(e * e), cost += rays(x, y);
      }
    pixels.update();
    // 12 samples: 10 per million leaves none out.
    EXPECT_NEAR(pixels.imageFactor(), std::sqrt(cost / error), 1e-5 * std::sqrt(cost / error)) << pass;
  }
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      Color sum(0.f);
      int n = 0;
      for (int yy = std::max(0, y - 1); yy <= std::min(H - 1, y + 1); ++yy)
        for (int xx = std::max(0, x - 1); xx <= std::min(W - 1, x + 1); ++xx)
          sum += (value(xx, yy, 0) + value(xx, yy, 1)) / 2.f, ++n;
      Color expected = sum / float(n), got = pixels.estimate(x, y);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 1e-5f * (1 + expected[c])) << x << " " << y;
    }
}

// The path estimator under a cache the test fills: slots by parity ask for
// the largest split or the smallest survival, both clamped (and the split
// capped by the path's product of factors). Nothing updates it during the
// render.
class FixedCachePath final : public PixelIntegrator {
 public:
  FixedCachePath(PathTracerSettings s, ContinuationCache& cache) : estimator_(s), cache_(cache) {}
  std::string splitRefusal() const override { return ""; }

 protected:
  Color Li(const Ray&, const Scene&, Sampler&, uint64_t&) const override { return Color(0.f); }
  Color pixelLi(int, int, const Ray& ray, const Scene& scene, Sampler& sampler, uint64_t& rays) const override {
    RrsView view{&cache_, cache_.threadSums(), estimator_.settings().rrs, true, Color(1.f), 1.f};
    return estimator_.Li(ray, scene, sampler, rays, nullptr, &view);
  }

 private:
  PathEstimator estimator_;
  ContinuationCache& cache_;
};

std::unique_ptr<Film> renderWithWrongCache(const SceneFile& sf, uint64_t spp, const char* params) {
  ContinuationCache cache(sf.scene->bounds(), 4, 1);
  ContinuationCache::Sums* sums = cache.threadSums();
  // Even slots: mean 10⁴ with variance 10⁸ (both rules split 20-fold);
  // odd ones: 10⁻⁶ without variance (both keep 1 path in 20).
  for (size_t slot = 0; slot < cache.slotCount(); ++slot)
    for (float v : {2e4f, 0.f}) cache.record(sums, slot, Color(slot % 2 == 0 ? v : 1e-6f), 3.0);
  cache.update();
  Params p(YAML::Load(params), "<test>", "integrator");
  FixedCachePath integrator(PathTracerSettings::read(p), cache);
  auto film = std::make_unique<Film>(sf.scene->camera.width(), sf.scene->camera.height());
  RenderOptions options;
  options.seed = 9;
  options.budget.spp = spp;
  renderLoop(*sf.scene, integrator, *film, sf.sampler, options);
  return film;
}

// The furnace (albedo 0.5, emission 1): L = 2 exactly, every pixel.
TEST(RouletteSplitting, WrongCacheLeavesTheFurnaceUnbiased) {
  SceneFile sf = loadSceneFromString(furnaceScene(0.5f), "furnace.yaml");
  for (const char* params : {"{rrs: adrrs}", "{rrs: ears}"}) {
    auto film = renderWithWrongCache(sf, 256, params);
    EXPECT_EQ(film->nonFiniteCount(), 0u) << params;
    EXPECT_TRUE(meanMatches(*film, 2.0, 1e-3)) << params;
  }
}

TEST(RouletteSplitting, WrongCacheLeavesCornellBoxUnbiased) {
  SceneFile sf = loadShippedScene("cornell-box", 24, 24);
  auto film = renderWithWrongCache(sf, 512, "{rrs: adrrs}");
  EXPECT_EQ(film->nonFiniteCount(), 0u);
  auto reference = regionMeans(*renderScene(sf, {"path", "{}", 1024, 100}), 3, 3);
  EXPECT_EQ(compareRegions(regionMeans(*film, 3, 3), reference, 1e-3), "");
}

// The cache and the pixel estimates learn between passes, from exact sums
// and per-pixel records: the same bits with one thread or two.
TEST(RouletteSplitting, SameSeedIsBitIdenticalWithOneAndTwoThreads) {
  SceneFile s = loadShippedScene("cornell-box", 32, 32);
  for (const char* params : {"{rrs: ears, rrs_warmup: 2, rrs_min_samples: 8}", "{rrs: adrrs, rrs_warmup: 2}"}) {
    Image one = renderScene(s, {"path", params, 8, 42, 1})->image();
    Image two = renderScene(s, {"path", params, 8, 42, 2})->image();
    ASSERT_EQ(one.pixels.size(), two.pixels.size());
    EXPECT_EQ(std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(Color)), 0) << params;
    // … and the learned factors changed the image.
    Image classic = renderScene(s, {"path", "{}", 8, 42, 1})->image();
    EXPECT_NE(std::memcmp(one.pixels.data(), classic.pixels.data(), one.pixels.size() * sizeof(Color)), 0) << params;
  }
}

TEST(RouletteSplitting, RefusesWhatCannotSplitOrLearn) {
  SceneFile scene = loadShippedScene("cornell-box", 8, 8);
  const std::vector<std::pair<std::string, std::string>> refused = {
      {"path", "{rrs: ears, engine: wavefront}"},
      {"path", "{rrs: ears, first_bounce_samples: 2}"},
      {"path", "{rrs: adrrs, mis: variance_aware}"},
      {"path", "{rrs: ears, max_depth: -1}"},
      {"path", "{rrs_warmup: 2}"},  // a key of adrrs and ears only
      {"guided", "{rrs: ears}"},
  };
  for (const auto& [integrator, params] : refused)
    EXPECT_THROW(renderScene(scene, {integrator, params, 1, 1}), ConfigError) << integrator << " " << params;
  // What it learned from earlier passes' numbers must not be correlated
  // with a later pass's: low-discrepancy samplers are refused.
  SceneFile sobol = loadShippedScene("cornell-box", 8, 8, "sampler: {type: sobol}");
  for (const char* params : {"{rrs: ears}", "{rrs: adrrs}", "{mis: variance_aware}"})
    EXPECT_THROW(renderScene(sobol, {"path", params, 1, 1}), std::invalid_argument) << params;
  EXPECT_NO_THROW(renderScene(sobol, {"path", "{}", 1, 1}));
  RenderSpec adaptive{"path", "{rrs: ears}", 4, 1};
  adaptive.adaptive.enabled = true;
  EXPECT_ANY_THROW(renderScene(scene, adaptive));
}

}  // namespace
}  // namespace lb::test
