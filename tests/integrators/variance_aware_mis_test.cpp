// Variance-aware MIS (integrators/path_estimator/variance_aware_mis.h):
//  * the factor c = M/V against the definition, computed another way (two
//    passes over the explicit samples, zeros included);
//  * the table pools a block's pixels and counts the samples it was not
//    told about (zeros) from the pass and light-sample counts;
//  * the path estimator stays unbiased under any factors, even absurd ones
//    (weights sum to 1 whatever c is): region z-tests against the power
//    heuristic on the Cornell box and Veach's MIS scene;
//  * the learned factors leave the image thread-count independent;
//  * the settings that cannot learn per pixel are refused.
#include <gtest/gtest.h>
#include <cstring>
#include <random>
#include "integrators/integrator.h"
#include "integrators/path_estimator/path_estimator.h"
#include "tests/support/render_helpers.h"

namespace lb::test {
namespace {

// M / V straight from the samples: the mean, then the mean squared deviation.
double factorByDefinition(const std::vector<double>& x) {
  double mean = 0, moment = 0, variance = 0;
  for (double v : x) mean += v, moment += v * v;
  mean /= double(x.size()), moment /= double(x.size());
  for (double v : x) variance += (v - mean) * (v - mean);
  variance /= double(x.size());
  return moment / variance;
}

TEST(VarianceAwareMis, FactorIsSecondMomentOverVariance) {
  std::mt19937 rng(7);
  std::exponential_distribution<double> exponential(3.0);
  std::uniform_real_distribution<double> uniform(0.9, 1.1);
  for (int trial = 0; trial < 3; ++trial) {
    // Heavy-tailed, nearly constant, and mostly zero: c near 2, large, and near 1.
    std::vector<double> x(500);
    for (size_t i = 0; i < x.size(); ++i)
      x[i] = trial == 0 ? exponential(rng) : trial == 1 ? uniform(rng) : (i % 50 == 0 ? exponential(rng) : 0.0);
    double sum = 0, squares = 0;
    for (double v : x) sum += v, squares += v * v;
    double expected = factorByDefinition(x);
    EXPECT_NEAR(VarianceAwareMis::factorFromSums(sum, squares, double(x.size())), expected, 1e-4 * expected) << trial;
  }
  // No evidence: c = 1. A constant estimate: the cap.
  EXPECT_EQ(VarianceAwareMis::factorFromSums(0, 0, 100), 1.f);
  EXPECT_EQ(VarianceAwareMis::factorFromSums(0.1 * 100, 0.01 * 100, 100), VarianceAwareMis::MaxFactor);
  EXPECT_EQ(VarianceAwareMis::factorFromSums(1, 1, 0), 1.f);
}

TEST(VarianceAwareMis, TablePoolsBlocksAndCountsUnrecordedZeros) {
  // A 6 × 5 image in blocks of 4: block (0, 0) has 16 pixels, block (1, 1) 2 × 1.
  const int passes = 2, lightSamples = 3;
  VarianceAwareMis table(6, 5, 4);
  table.record(0, 0, 3, MisTechnique::Light, 2.f);
  table.record(3, 3, 3, MisTechnique::Light, 0.5f);
  table.record(1, 2, 3, MisTechnique::Bsdf, 4.f);
  table.record(5, 4, 3, MisTechnique::Light, 1.f);
  table.record(4, 4, 3, MisTechnique::Light, 3.f);
  table.record(4, 4, 20, MisTechnique::Light, 3.f);  // beyond MaxLength: ignored
  EXPECT_EQ(table.factor(0, 0, 3, MisTechnique::Light), 1.f);  // before finish(): 1
  table.finish(passes, lightSamples);

  auto withZeros = [](std::vector<double> x, size_t n) {
    x.resize(n, 0.0);
    return factorByDefinition(x);
  };
  double light00 = withZeros({2, 0.5}, 16 * passes * lightSamples);
  double bsdf00 = withZeros({4}, 16 * passes);
  double light11 = withZeros({1, 3}, 2 * passes * lightSamples);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      EXPECT_NEAR(table.factor(x, y, 3, MisTechnique::Light), light00, 1e-4 * light00);
      EXPECT_NEAR(table.factor(x, y, 3, MisTechnique::Bsdf), bsdf00, 1e-4 * bsdf00);
      EXPECT_EQ(table.factor(x, y, 2, MisTechnique::Light), 1.f);  // another length: nothing recorded
    }
  EXPECT_NEAR(table.factor(4, 4, 3, MisTechnique::Light), light11, 1e-4 * light11);
  EXPECT_EQ(table.factor(4, 0, 3, MisTechnique::Light), 1.f);  // block (1, 0): nothing recorded
  EXPECT_EQ(table.factor(4, 4, 20, MisTechnique::Light), 1.f);
}

// The path estimator under a table of deliberately wrong factors: the
// light's cap in some blocks, the BSDF's in others, and mild random ones
// elsewhere. Unweighted, such factors would bias nothing only if the weights
// of each pair of techniques still sum to 1.
class FixedFactorsPath final : public PixelIntegrator {
 public:
  FixedFactorsPath(PathTracerSettings s, VarianceAwareMis& table) : estimator_(s), table_(table) {}
  std::string splitRefusal() const override { return ""; }

 protected:
  Color Li(const Ray&, const Scene&, Sampler&, uint64_t&) const override { return Color(0.f); }
  Color pixelLi(int x, int y, const Ray& ray, const Scene& scene, Sampler& sampler, uint64_t& rays) const override {
    VarianceAwareView view{&table_, x, y, false};
    return estimator_.Li(ray, scene, sampler, rays, &view);
  }

 private:
  PathEstimator estimator_;
  VarianceAwareMis& table_;
};

// `cap`: kinds 0 and 1 give their technique the largest factor (every
// sample the same value); otherwise c = 4 (3 of a block's 4 samples the same
// value, one zero), still wrong but not an estimator of one technique alone.
void expectWrongFactorsUnbiased(const SceneFile& sf, uint64_t spp, int regions, bool cap) {
  const int W = sf.scene->camera.width(), H = sf.scene->camera.height(), block = 2;
  VarianceAwareMis table(W, H, block);
  std::mt19937 rng(3);
  std::exponential_distribution<float> exponential(1.f);
  for (int by = 0; by * block < H; ++by)
    for (int bx = 0; bx * block < W; ++bx)
      for (int length = 2; length <= VarianceAwareMis::MaxLength; ++length) {
        int kind = (bx + by + length) % 3;
        for (int y = by * block; y < std::min(H, (by + 1) * block); ++y)
          for (int x = bx * block; x < std::min(W, (bx + 1) * block); ++x) {
            // kind 0: the light samples' factor large (the cap, or 4); kind 1:
            // the BSDF's; kind 2: exponential values for both.
            bool skip = !cap && x == bx * block && y == by * block;  // one zero sample
            if (kind == 0 && !skip) table.record(x, y, length, MisTechnique::Light, 1.f);
            if (kind == 1 && !skip) table.record(x, y, length, MisTechnique::Bsdf, 1.f);
            if (kind == 2) {
              table.record(x, y, length, MisTechnique::Light, exponential(rng));
              table.record(x, y, length, MisTechnique::Bsdf, exponential(rng));
            }
          }
      }
  table.finish(1, 1);
  ASSERT_EQ(table.factor(0, 0, 3, MisTechnique::Light), cap ? VarianceAwareMis::MaxFactor : 4.f);  // kind 0

  Params params(YAML::Load("{mis: variance_aware}"), "<test>", "integrator");
  FixedFactorsPath integrator(PathTracerSettings::read(params), table);
  Film film(W, H);
  RenderOptions options;
  options.seed = 5;
  options.budget.spp = spp;
  renderLoop(*sf.scene, integrator, film, sf.sampler, options);
  EXPECT_EQ(film.nonFiniteCount(), 0u);
  auto reference = regionMeans(*renderScene(sf, {"path", "{}", 2 * spp, 100}), regions, regions);
  EXPECT_EQ(compareRegions(regionMeans(film, regions, regions), reference, 1e-3), "");
}

// On the Cornell box even capped factors (light sampling alone, or BSDF
// sampling alone, wherever the other could sample) keep the films' variance
// estimate reliable. On Veach's plates and tiny lights, one technique alone
// has the rare huge samples that make it unreliable (path_variants_test.cpp),
// so there the wrong factors are 4, not the cap.
TEST(VarianceAwareMis, WrongFactorsLeaveCornellBoxUnbiased) {
  expectWrongFactorsUnbiased(loadShippedScene("cornell-box", 24, 24), 1024, 3, true);
}

TEST(VarianceAwareMis, WrongFactorsLeaveVeachMisSceneUnbiased) {
  expectWrongFactorsUnbiased(loadShippedScene("veach-mis", 32, 20), 1024, 4, false);
}

// Pilot passes learn between passes; each pass's pixels are written by one
// thread, so the image is bit-identical at any thread count.
TEST(VarianceAwareMis, SameSeedIsBitIdenticalWithOneAndTwoThreads) {
  SceneFile s = loadShippedScene("veach-mis", 32, 20);
  const char* params = "{mis: variance_aware, pilot_passes: 2, factor_block: 4, shadow_rays: 2}";
  Image one = renderScene(s, {"path", params, 6, 42, 1})->image();
  Image two = renderScene(s, {"path", params, 6, 42, 2})->image();
  ASSERT_EQ(one.pixels.size(), two.pixels.size());
  EXPECT_EQ(std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(Color)), 0);
  // … and the learned factors changed the image: it differs from the balance heuristic's.
  Image balance = renderScene(s, {"path", "{mis: balance, shadow_rays: 2}", 6, 42, 1})->image();
  EXPECT_NE(std::memcmp(one.pixels.data(), balance.pixels.data(), one.pixels.size() * sizeof(Color)), 0);
}

TEST(VarianceAwareMis, RefusesWhatCannotLearnPerPixel) {
  SceneFile scene = loadShippedScene("cornell-box", 8, 8);
  const std::vector<std::pair<std::string, std::string>> refused = {
      {"path", "{mis: variance_aware, engine: wavefront}"},
      {"path", "{mis: variance_aware, first_bounce_samples: 2}"},
      {"path", "{mis: variance_aware, emission_selection: 0.5}"},
      {"path", "{mis: balance, pilot_passes: 2}"},  // a key of variance_aware only
      {"guided", "{mis: variance_aware}"},
  };
  for (const auto& [integrator, params] : refused)
    EXPECT_THROW(renderScene(scene, {integrator, params, 1, 1}), ConfigError) << integrator << " " << params;
  // Adaptive sampling needs per-pixel estimates with nothing learned from a pass.
  RenderSpec adaptive{"path", "{mis: variance_aware}", 4, 1};
  adaptive.adaptive.enabled = true;
  EXPECT_ANY_THROW(renderScene(scene, adaptive));
}

}  // namespace
}  // namespace lb::test
