// The `guided` integrator (issue 18): both learning methods estimate the same
// image as the path tracer (guiding changes the variance, never the mean), the
// mixture's density is the density its sampling follows for trained
// distributions, and images do not depend on the thread count. The learned
// structures themselves (the quadtree) are tested in guided_quadtree_test.cpp.
#include "integrators/guided/guided.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include "core/error.h"
#include "integrators/guided/sphere_map.h"
#include "integrators/registry.h"
#include "integrators/render_loop.h"
#include "tests/support/render_helpers.h"
#include "tests/support/repeats.h"
#include "tests/support/statistics.h"

namespace lb::test {
namespace {

constexpr double Alpha = 1e-3;

// Small enough for CI, large enough that the guide is used: at 24×24 the
// paper's split threshold (12000 records) would leave one spatial leaf, so
// the tests split at 300 and train 6 iterations (63 spp); Q-learning's grid
// is 4 cells long, so that its tables reach the updates they need before
// they guide (q_learning.cpp).
const char* const Methods[][2] = {
    {"sdtree", "{method: sdtree, spatial_threshold: 300, training_iterations: 6}"},
    {"qlearning", "{method: qlearning, grid_resolution: 4}"},
};

// Region means over independent runs (each with its own training, so the
// learned distribution's randomness is part of the spread), against the path
// tracer's, by Welch t-tests (tests/support/repeats.h); and the whole image's
// mean luminance, with the check that the comparison could see an error of
// `detectable` (relative) with probability 0.9. The sharp test of the
// mixture is the χ² below; these show the whole estimator's mean unchanged.
void expectAgreementWithPath(const char* scene, int w, int h, uint64_t spp, double detectable) {
  const std::string extra = "{}";
  const int Seeds = 12, Regions = 2;
  SceneFile sf = loadShippedScene(scene, w, h);
  SeedMeans path = seedMeans(sf, {"path", "{}", spp}, Seeds, Regions, Regions, 300, extra);
  for (const auto& m : Methods) {
    SeedMeans guided = seedMeans(sf, {"guided", m[1], spp}, Seeds, Regions, Regions, 700, extra);
    EXPECT_EQ(guided.nonFinite, 0u) << m[0];
    std::string failures = compareSeedMeans(guided, path, Alpha, Regions * Regions * 3 * 2);
    EXPECT_TRUE(failures.empty()) << scene << ", " << m[0] << ":" << failures;
    const RunningStats& a = guided.imageLuminance;
    const RunningStats& r = path.imageLuminance;
    double se = std::sqrt(a.varianceOfMean() + r.varianceOfMean());
    double bound = studentCritical(sidak(Alpha, 2), Seeds - 1) * se;
    std::cout << scene << " " << m[0] << ": mean luminance " << a.mean << " vs path " << r.mean << ", bound ±" << bound
              << " (" << 100 * bound / r.mean << " %)\n";
    EXPECT_LE(std::abs(a.mean - r.mean), bound) << scene << ", " << m[0];
    EXPECT_LE(bound + normalCritical(0.2) * se, detectable * r.mean)
        << scene << ", " << m[0] << ": too noisy to see " << 100 * detectable << " %";
  }
}

TEST(Guided, AgreesWithPathOnTheCornellBox) { expectAgreementWithPath("cornell-box", 24, 24, 256, 0.05); }
TEST(Guided, AgreesWithPathOnVeachsMisScene) { expectAgreementWithPath("veach-mis", 32, 20, 512, 0.075); }
TEST(Guided, AgreesWithPathOnTheNarrowDoorScene) { expectAgreementWithPath("door-narrow", 32, 24, 1024, 0.075); }

// A sampler that hands out given numbers: the lobe choice, the 2-D direction
// number, then 0.5 for anything else (roulette is off in these tests).
class GivenNumbers final : public Sampler {
 public:
  void set(float uLobe, Vec2 u) { values_[0] = uLobe, values_[1] = u.x, values_[2] = u.y, next_ = 0; }
  void start(uint64_t, uint64_t) override { next_ = 0; }
  float get1D() override { return next_ < 3 ? values_[next_++] : 0.5f; }
  Vec2 get2D() override {
    float a = get1D();
    return {a, get1D()};
  }
  std::unique_ptr<Sampler> clone() const override { return std::make_unique<GivenNumbers>(*this); }
  uint64_t seed() const override { return 0; }

 private:
  float values_[3] = {0, 0, 0};
  int next_ = 0;
};

// A trained integrator: the SD-tree's preprocess, or Q-learning's passes.
std::unique_ptr<GuidedPathTracer> trained(const SceneFile& sf, const std::string& params, int passes) {
  YAML::Node node = YAML::Load(params);
  Params p(node, "test.yaml", "integrator");
  auto integrator = std::make_unique<GuidedPathTracer>(GuidedSettings::read(p));
  IndependentSampler sampler(11);
  integrator->preprocess(*sf.scene, sampler);
  Film film(sf.scene->camera.width(), sf.scene->camera.height());
  PassStats stats;
  for (int i = 0; i < passes; ++i) integrator->renderPass(*sf.scene, film, sampler, uint64_t(i), stats);
  return integrator;
}

// χ² over the equal-area square of sphere_map.h, in 64 × 64 cells plus one
// for missing samples. Both guides' densities are constant on dyadic squares
// of it (Q's bins; quadtree leaves, at most 10 levels deep here), and the
// horizons of axis-aligned surfaces (the Cornell box's walls, floor and
// ceiling; the test uses only those) are cell edges too: a 16 × 16 midpoint sum per cell integrates the guide exactly and the
// smooth BSDF density to high order. Missing samples must match the mass
// 1 − ∫ pdf, so a density with too much or too little mass fails.
Chi2Result squareHistogramTest(const std::function<std::optional<Vec3>(Vec2, float)>& sample,
                               const std::function<double(const Vec3&)>& pdf, size_t samples, uint64_t seed) {
  const int Cells = 64, Sub = 16, Fine = Cells * Sub;
  std::vector<double> expected(Cells * Cells + 1, 0), observed(Cells * Cells + 1, 0);
  double total = 0;
  for (int y = 0; y < Fine; ++y)
    for (int x = 0; x < Fine; ++x) {
      Vec3 w = guiding::directionFromSquare({(x + 0.5f) / Fine, (y + 0.5f) / Fine});
      double mass = pdf(w) * 4 * M_PI / (double(Fine) * Fine);
      expected[size_t((y / Sub) * Cells + x / Sub)] += mass * double(samples);
      total += mass;
    }
  expected[Cells * Cells] = std::max(0.0, 1 - total) * double(samples);
  // A direction drawn on a cell's edge maps back to the square with float
  // rounding (about 1e-7) and may land in the neighbour, which can hold no
  // mass: a few in 10⁵ samples. A token mass per cell lets χ² pool such
  // cells instead of failing outright on one stray sample; a density that is
  // wrong by more than rounding still fails (tested by breaking it).
  for (double& e : expected) e += 1e-9 * double(samples);
  Pcg32 rng(seed, 5);
  for (size_t i = 0; i < samples; ++i) {
    Vec2 u = rng.next2D();
    auto w = sample(u, rng.next1D());
    if (!w) {
      observed[Cells * Cells] += 1;
      continue;
    }
    Vec2 c = guiding::squareFromDirection(glm::normalize(*w));
    observed[size_t(int(c.y * Cells) * Cells + int(c.x * Cells))] += 1;
  }
  return chi2Test(observed, expected);
}

// The path estimator's mixture sampling (PathEstimator::scatter, which the
// guided integrator runs) against the mixture density c·p_bsdf + (1−c)·p_guide,
// each component's density evaluated on its own (the quadtree's product of
// quadrant shares, Q's bin weights; sampling halves the square or searches a
// cumulative table), at points the camera sees on a trained Cornell box.
// scatter() ends the path for a direction the BSDF does not scatter into (the
// guide's mass below the surface): those samples are missing, and the test's
// density is 0 there, so exactly that mass is expected to be missing. The
// weight scatter() gives each direction must divide by that same density,
// and the guide alone is tested the same way.
TEST(Guided, MixtureSamplingFollowsTheMixtureDensity) {
  SceneFile sf = loadShippedScene("cornell-box", 24, 24);
  YAML::Node none = YAML::Load("{rr: false}");
  Params pp(none, "test.yaml", "integrator");
  PathEstimator estimator(PathTracerSettings::read(pp));
  // Points on the floor, the walls and the ceiling; points on the boxes'
  // rotated faces are skipped, since their horizons cut the histogram's cells.
  const Vec2 pixels[] = {{12, 22}, {5, 21}, {1, 12}, {22, 12}, {12, 1}, {12, 20}, {4, 12}, {20, 6}};
  int tests = 0, guidedPoints = 0;
  for (const auto& m : Methods) {
    bool q = m[0] == std::string("qlearning");
    std::string params = q ? m[1] : std::string(m[1]).insert(1, "max_quadtree_depth: 10, ");
    auto integrator = trained(sf, params, q ? 64 : 0);
    auto guide = integrator->method().makeGuide(0.4f);
    for (Vec2 px : pixels) {
      SurfaceInteraction si;
      ASSERT_TRUE(sf.scene->intersect(sf.scene->camera.generateRay(px + Vec2(0.5f)), si));
      if (std::max({std::abs(si.ng.x), std::abs(si.ng.y), std::abs(si.ng.z)}) < 0.9999f) continue;
      BSDF bsdf(si);
      if (!guide->prepare(si, bsdf)) continue;  // nothing learned here
      ++guidedPoints;
      GivenNumbers numbers;
      size_t weighted = 0, weightMismatches = 0;
      auto mixture = [&](const Vec3& wi) {
        if (isBlack(bsdf.eval(si.wo, wi, TransportMode::Radiance).f)) return 0.0;
        return double(guide->mixturePdf(bsdf.pdf(si.wo, wi), wi));
      };
      auto r = squareHistogramTest(
          [&](Vec2 u, float uLobe) -> std::optional<Vec3> {
            numbers.set(uLobe, u);
            PathState next;
            if (!estimator.scatter(next, si, bsdf, numbers, 0, guide.get())) return std::nullopt;
            // The weight scatter() gave the direction must use the density
            // the histogram checks: f·|cos θ| / (c·p_bsdf + (1 − c)·p_guide).
            const Vec3& d = next.ray.d;
            double density = mixture(d);
            Color expectedBeta = bsdf.eval(si.wo, d, TransportMode::Radiance).f *
                                 float(absDot(d, bsdf.shadingNormal()) / density);
            ++weighted;
            weightMismatches += std::abs(next.prevPdf - density) > 1e-4 * density ||
                                std::abs(luminance(next.beta) - luminance(expectedBeta)) > 1e-4f * luminance(expectedBeta);
            return d;
          },
          mixture, 200000, 1000 + uint64_t(tests));
      EXPECT_LE(weightMismatches, weighted / 1000) << m[0] << " at pixel " << px.x << "," << px.y
                                                   << ": scatter's weight is not f cos / mixture density";
      // The guide alone; the density sample() reports on its way down must be
      // pdf() at the direction it returns (a direction on a cell's edge may
      // round into the neighbour: allowed for one sample in a thousand).
      size_t mismatches = 0, drawn = 0;
      auto alone = squareHistogramTest(
          [&](Vec2 u, float) -> std::optional<Vec3> {
            float reported = 0;
            Vec3 d = guide->sample(u, &reported);
            float evaluated = guide->pdf(d);
            ++drawn;
            mismatches += std::abs(reported - evaluated) > 1e-4f * evaluated;
            return d;
          },
          [&](const Vec3& wi) { return double(guide->pdf(wi)); }, 200000, 2000 + uint64_t(tests));
      EXPECT_LE(mismatches, drawn / 1000) << m[0] << " at pixel " << px.x << "," << px.y;
      ++tests;
      EXPECT_TRUE(r.passed(Alpha / 12)) << m[0] << " mixture at pixel " << px.x << "," << px.y << ": " << r.message
                                        << " p = " << r.pValue;
      EXPECT_TRUE(alone.passed(Alpha / 12))
          << m[0] << " guide at pixel " << px.x << "," << px.y << ": " << alone.message << " p = " << alone.pValue;
    }
  }
  EXPECT_GE(guidedPoints, 6) << "the trained guides should cover most of these points";
}

// 64×64 pixels (16 tiles) on 1 and 4 threads, 32 passes: Q-learning's
// tables guide after a few passes, so later passes depend on what earlier
// ones learned, which must not depend on which thread rendered which tile.
TEST(Guided, SameSeedGivesTheSameImageWithOneAndFourThreads) {
  SceneFile sf = loadShippedScene("cornell-box", 64, 64);
  for (const auto& m : Methods) {
    Image one = renderScene(sf, {"guided", m[1], 32, 3, 1})->image();
    Image four = renderScene(sf, {"guided", m[1], 32, 3, 4})->image();
    Image other = renderScene(sf, {"guided", m[1], 32, 4, 4})->image();
    EXPECT_EQ(one.pixels, four.pixels) << m[0];
    EXPECT_NE(one.pixels, other.pixels) << m[0];
  }
}

// Learned roulette and splitting (rrs: adrrs | ears) inside guided: the
// same image in expectation as the path tracer's (each guided method with
// each rule, the cache learned from the runs' own passes, warm-up short so
// most passes split), and the same bits with one thread or two.
const char* const LearnedRoulette[] = {"adrrs", "ears"};

std::string withRrs(const char* method, const char* rrs) {
  std::string params = method;
  params.pop_back();
  return params + ", rrs: " + rrs + ", rrs_warmup: 2, rrs_min_samples: 8}";
}

TEST(Guided, LearnedRouletteAndSplittingAgreeWithPath) {
  const int Seeds = 12, Regions = 2;
  SceneFile sf = loadShippedScene("cornell-box", 24, 24);
  SeedMeans path = seedMeans(sf, {"path", "{}", 1024}, Seeds, Regions, Regions, 300);
  for (const auto& m : Methods)
    for (const char* rrs : LearnedRoulette) {
      std::string params = withRrs(m[1], rrs);
      SeedMeans guided = seedMeans(sf, {"guided", params, 256}, Seeds, Regions, Regions, 900);
      EXPECT_EQ(guided.nonFinite, 0u) << params;
      std::string failures = compareSeedMeans(guided, path, Alpha, Regions * Regions * 3 * 4);
      EXPECT_TRUE(failures.empty()) << params << ":" << failures;
      const RunningStats& a = guided.imageLuminance;
      const RunningStats& r = path.imageLuminance;
      double se = std::sqrt(a.varianceOfMean() + r.varianceOfMean());
      double bound = studentCritical(sidak(Alpha, 4), Seeds - 1) * se;
      std::cout << params << ": mean luminance " << a.mean << " vs path " << r.mean << ", bound ±" << bound << " ("
                << 100 * bound / r.mean << " %)\n";
      EXPECT_LE(std::abs(a.mean - r.mean), bound) << params;
      EXPECT_LE(bound + normalCritical(0.2) * se, 0.05 * r.mean) << params << ": too noisy to see 5 %";
    }
}

TEST(Guided, LearnedRouletteIsBitIdenticalWithOneAndTwoThreadsAndSplits) {
  SceneFile sf = loadShippedScene("cornell-box", 32, 32);
  for (const auto& m : Methods)
    for (const char* rrs : LearnedRoulette) {
      std::string params = withRrs(m[1], rrs);
      Image one = renderScene(sf, {"guided", params, 8, 5, 1})->image();
      Image two = renderScene(sf, {"guided", params, 8, 5, 2})->image();
      EXPECT_EQ(one.pixels, two.pixels) << params;
      // The learned factors changed the image (against the warm-up's classic roulette throughout).
      std::string warmUp = params.substr(0, params.size() - 1) + ", rrs_warmup: 100}";
      warmUp.replace(warmUp.find("rrs_warmup: 2, "), std::strlen("rrs_warmup: 2, "), "");
      EXPECT_NE(one.pixels, renderScene(sf, {"guided", warmUp, 8, 5, 1})->image().pixels) << params;
    }
}

TEST(Guided, RefusesSettingsItCannotHonour) {
  for (const char* yaml :
       {"{sampling: cosine}", "{engine: wavefront}", "{first_bounce_samples: 2}", "{bsdf_fraction: 0}",
        "{debug_point: '3'}", "{method: sdtree, grid_resolution: 8}", "{method: qlearning, training_iterations: 2}"}) {
    YAML::Node node = YAML::Load(yaml);
    Params p(node, "x.yaml", "integrator");
    EXPECT_THROW(makeIntegrator("guided", p, "x.yaml", 1), ConfigError) << yaml;
  }
  // Learned roulette learns from every pass: low-discrepancy samplers are refused.
  SceneFile sobol = loadShippedScene("cornell-box", 8, 8, "sampler: {type: sobol}");
  for (const char* rrs : LearnedRoulette)
    EXPECT_THROW(renderScene(sobol, {"guided", withRrs(Methods[0][1], rrs), 1, 1}), std::invalid_argument) << rrs;
  EXPECT_NO_THROW(renderScene(sobol, {"guided", Methods[0][1], 1, 1}));
}

}  // namespace
}  // namespace lb::test
