// Variance-aware MIS in BDPT (bdpt mis: variance_aware; strategy_factors.h):
//  * the table pools a block's pixels and turns the pass estimates into
//    c = M/V (the factor itself is variance_aware_mis_test.cpp's);
//  * BDPT stays unbiased under deliberately wrong factors (region z-tests
//    against the power heuristic): a path's strategies must all read the
//    factor of the pixel the path lands in, or its weights stop summing to 1;
//  * learned factors: unbiased, thread-count independent, not the balance
//    heuristic's image; refusals.
// The weights themselves against the definition: bidirectional_mis_test.cpp.
#include <gtest/gtest.h>
#include <cstring>
#include <random>
#include "integrators/bdpt/bdpt.h"
#include "integrators/render_loop.h"
#include "tests/support/render_helpers.h"

namespace lb::test {
namespace {

using bidir::StrategyFactors;

TEST(StrategyFactors, PoolsBlocksAndCountsUnrecordedZeros) {
  StrategyFactors table(6, 5, 4);
  table.record(0, 0, 2, 1, 2.0);
  table.record(3, 3, 2, 1, 0.5);
  table.record(5, 4, 0, 3, 1.0);
  table.record(0, 0, 9, 1, 1.0);  // 9 segments: beyond MaxSegments, ignored
  EXPECT_EQ(table.factor(Vec2(0.5f), 2, 1), 1.0);  // before finish()
  table.finish(2);
  auto byDefinition = [](std::vector<double> x, size_t n) {
    x.resize(n, 0.0);
    double mean = 0, moment = 0, variance = 0;
    for (double v : x) mean += v / double(n), moment += v * v / double(n);
    for (double v : x) variance += (v - mean) * (v - mean) / double(n);
    return moment / variance;
  };
  EXPECT_NEAR(table.factor(Vec2(2.5f, 1.5f), 2, 1), byDefinition({2, 0.5}, 16 * 2), 1e-5);
  EXPECT_NEAR(table.factor(Vec2(4.2f, 4.9f), 0, 3), byDefinition({1}, 2 * 2), 1e-5);  // an edge block of 2 pixels
  EXPECT_EQ(table.factor(Vec2(4.2f, 0.5f), 2, 1), 1.0);  // nothing recorded there
  EXPECT_EQ(table.factor(Vec2(0.5f), 9, 1), 1.0);
  EXPECT_EQ(table.factor(Vec2(-3.f, 99.f), 0, 3), table.factor(Vec2(0.f, 4.f), 0, 3));  // clamped to the image
}

// Factors of three kinds, by block and strategy: c = 4 (three of a block's
// four pixels record the same value), none recorded (c = 1), and random
// values (c between 1 and about 3).
std::unique_ptr<StrategyFactors> wrongFactors(int W, int H) {
  const int block = 2;
  auto table = std::make_unique<StrategyFactors>(W, H, block);
  std::mt19937 rng(3);
  std::exponential_distribution<double> exponential(1.0);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      for (int k = 1; k <= StrategyFactors::MaxSegments; ++k)
        for (int s = 0; s <= k; ++s) {
          int t = k + 1 - s, kind = (x / block + 2 * (y / block) + s + 2 * t) % 3;
          bool first = x % block == 0 && y % block == 0;
          if (kind == 0 && !first) table->record(x, y, s, t, 1.0);
          if (kind == 2) table->record(x, y, s, t, exponential(rng));
        }
  table->finish(1);
  return table;
}

void expectWrongFactorsUnbiased(const SceneFile& sf, uint64_t spp, int regions) {
  const int W = sf.scene->camera.width(), H = sf.scene->camera.height();
  Params params(YAML::Load("{mis: variance_aware}"), "<test>", "integrator");
  Bdpt integrator(BdptSettings::read(params));
  integrator.setStrategyFactors(wrongFactors(W, H));
  Film film(W, H);
  RenderOptions options;
  options.seed = 5;
  options.budget.spp = spp;
  renderLoop(*sf.scene, integrator, film, sf.sampler, options);
  EXPECT_EQ(film.nonFiniteCount(), 0u);
  auto reference = regionMeans(*renderScene(sf, {"bdpt", "{}", spp, 100}), regions, regions);
  EXPECT_EQ(compareRegions(regionMeans(film, regions, regions), reference, 1e-3), "");
}

TEST(BdptVarianceAwareMis, WrongFactorsLeaveCornellBoxWithSpheresUnbiased) {
  expectWrongFactorsUnbiased(loadShippedScene("cornell-box-spheres", 24, 24), 512, 3);
}

TEST(BdptVarianceAwareMis, WrongFactorsLeaveVeachMisSceneUnbiased) {
  expectWrongFactorsUnbiased(loadShippedScene("veach-mis", 32, 20), 512, 4);
}

TEST(BdptVarianceAwareMis, LearnedFactorsAreUnbiasedAndThreadCountIndependent) {
  SceneFile s = loadShippedScene("cornell-box-spheres", 24, 24);
  const char* params = "{mis: variance_aware, pilot_passes: 4, factor_block: 4}";
  auto learned = renderScene(s, {"bdpt", params, 512, 7, 2});
  auto reference = regionMeans(*renderScene(s, {"bdpt", "{}", 512, 100}), 3, 3);
  EXPECT_EQ(compareRegions(regionMeans(*learned, 3, 3), reference, 1e-3), "");
  Image one = renderScene(s, {"bdpt", params, 8, 42, 1})->image();
  Image two = renderScene(s, {"bdpt", params, 8, 42, 2})->image();
  ASSERT_EQ(one.pixels.size(), two.pixels.size());
  EXPECT_EQ(std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(Color)), 0);
  Image balance = renderScene(s, {"bdpt", "{mis: balance}", 8, 42, 1})->image();
  EXPECT_NE(std::memcmp(one.pixels.data(), balance.pixels.data(), one.pixels.size() * sizeof(Color)), 0);
}

TEST(BdptVarianceAwareMis, RefusesWhatItCannotLearn) {
  SceneFile scene = loadShippedScene("cornell-box", 8, 8);
  EXPECT_THROW(renderScene(scene, {"bdpt", "{mis: variance_aware, regularize: true}", 1, 1}), ConfigError);
  EXPECT_THROW(renderScene(scene, {"bdpt", "{mis: power, pilot_passes: 2}", 1, 1}), ConfigError);
  EXPECT_THROW(renderScene(scene, {"bdpt", "{mis: variance_aware, factor_block: 3}", 1, 1}), ConfigError);
  // Learned from earlier passes: their numbers must be independent of later ones.
  SceneFile sobol = loadShippedScene("cornell-box", 8, 8, "sampler: {type: sobol}");
  EXPECT_ANY_THROW(renderScene(sobol, {"bdpt", "{mis: variance_aware}", 1, 1}));
  EXPECT_NO_THROW(renderScene(sobol, {"bdpt", "{mis: balance}", 1, 1}));
}

}  // namespace
}  // namespace lb::test
