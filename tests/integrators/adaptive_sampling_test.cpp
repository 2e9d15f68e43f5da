// Adaptive sampling (integrators/adaptive_sampling.h): the image (the
// estimating half) is unbiased — on an analytic scene, and on a caustic where
// the deciding half, whose counts depend on its own samples, is measurably
// biased (so the test would catch a scheme that decided and estimated with
// the same samples); the samples go where the error is; images do not depend
// on the thread count; integrators it cannot drive are refused.
#include "integrators/adaptive_sampling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include "integrators/registry.h"
#include "tests/support/render_helpers.h"
#include "tests/support/statistics.h"

namespace lb::test {
namespace {

constexpr double Alpha = 1e-3;

AdaptiveSettings adaptive(int passes, double target = 0) {
  AdaptiveSettings s;
  s.enabled = true, s.passes = passes, s.targetRelativeError = target;
  return s;
}

double meanLuminance(const Film& film) {
  Image img = film.image();
  double sum = 0;
  for (const Color& c : img.pixels) sum += luminance(c);
  return sum / double(img.pixels.size());
}

TEST(AdaptiveSampling, PointLightOverAPlaneIsAnalytic) {
  const float rho = 0.5f, I = 10.f, h = 2.f;
  SceneFile sf = loadSceneFromString(PointLightPlaneScene, "point-plane.yaml");
  RenderSpec spec{"path", "{max_depth: 2}", 64, 2};
  spec.adaptive = adaptive(4);
  auto film = renderScene(sf, spec);
  double exact = pointLightOverPlane(sf.scene->camera, Vec3(0.3f, h, 0.2f), I, rho);
  EXPECT_TRUE(meanMatches(*film, exact, Alpha));
}

// Both halves of adaptive runs on the sealed light (a light inside a glass
// sphere: a path tracer finds it only by hitting it through the glass, so a
// pixel's samples are mostly 0 and rarely large), with a target that stops
// pixels early, over independent seeds; against uniform path tracing's image
// mean. The estimating half agrees; the deciding half — a pixel stops when
// its own samples happen to look converged, i.e. when they have not yet met
// the rare bright paths — comes out low.
TEST(AdaptiveSampling, TheImageIsUnbiasedWhereDecidingFromItsOwnSamplesIsNot) {
  SceneFile sf = loadShippedScene("enclosed-light", 16, 12);
  const int Seeds = 80, Passes = 64;
  RunningStats estimating, deciding, uniform;
  for (int seed = 0; seed < Seeds; ++seed) {
    Params params(YAML::Load("{}"), "<test>", "integrator");
    auto integrator = makeIntegrator("path", params);
    auto* pixels = dynamic_cast<PixelIntegrator*>(integrator.get());
    ASSERT_NE(pixels, nullptr);
    auto sampler = makeSampler(sf.sampler, uint64_t(100 + seed), 16, 12);
    Film estimate(16, 12);
    AdaptiveSampling sampling(16, 12, adaptive(4, 0.3));
    PassStats stats;
    integrator->preprocess(*sf.scene, *sampler);
    for (int pass = 0; pass < Passes; ++pass)
      if (!sampling.renderPass(*sf.scene, *pixels, estimate, *sampler, uint64_t(pass), stats)) break;
    estimating.add(meanLuminance(estimate));
    deciding.add(meanLuminance(sampling.decidingHalf()));
    uniform.add(meanLuminance(*renderScene(sf, {"path", "{}", Passes, uint64_t(900 + seed)})));
  }
  auto t = [&](const RunningStats& a) {
    return (a.mean - uniform.mean) / std::sqrt(a.varianceOfMean() + uniform.varianceOfMean());
  };
  double critical = studentCritical(Alpha, Seeds - 1);
  std::cout << "image mean: estimating half " << estimating.mean << ", deciding half " << deciding.mean << ", uniform "
            << uniform.mean << "; t = " << t(estimating) << ", " << t(deciding) << " (critical " << critical << ")\n";
  EXPECT_LE(std::abs(t(estimating)), critical);
  EXPECT_LT(t(deciding), -critical) << "the deciding half should show the bias the split avoids";
}

// Where the samples went: each pixel's count (both halves) against its
// relative deviation σ_p/√(m_p² + 0.01) measured on an independent uniform
// render; Pearson's r must be positive beyond chance (t-test of r).
TEST(AdaptiveSampling, SamplesGoWhereTheErrorIs) {
  SceneFile sf = loadShippedScene("veach-mis", 32, 20);
  Params params(YAML::Load("{}"), "<test>", "integrator");
  auto integrator = makeIntegrator("path", params);
  auto* pixels = dynamic_cast<PixelIntegrator*>(integrator.get());
  auto sampler = makeSampler(sf.sampler, 5, 32, 20);
  Film estimate(32, 20);
  AdaptiveSampling sampling(32, 20, adaptive(8));
  PassStats stats;
  integrator->preprocess(*sf.scene, *sampler);
  for (int pass = 0; pass < 64; ++pass)
    sampling.renderPass(*sf.scene, *pixels, estimate, *sampler, uint64_t(pass), stats);
  auto independent = renderScene(sf, {"path", "{}", 256, 77});
  Image mean = independent->image(), variance = independent->varianceOfMean();
  std::vector<double> counts, deviation;
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 32; ++x) {
      const Color& v = variance.at(x, y);
      double m = luminance(mean.at(x, y));
      counts.push_back(double(sampling.drawn()[size_t(y) * 32 + x]));
      deviation.push_back(std::sqrt((double(v.r) + v.g + v.b) / 3 * 256) / std::sqrt(m * m + 0.01));
    }
  RunningStats a, b;
  for (size_t i = 0; i < counts.size(); ++i) a.add(counts[i]), b.add(deviation[i]);
  double cov = 0;
  for (size_t i = 0; i < counts.size(); ++i) cov += (counts[i] - a.mean) * (deviation[i] - b.mean);
  double n = double(counts.size());
  double r = cov / (n - 1) / std::sqrt(a.variance() * b.variance());
  double tr = r * std::sqrt((n - 2) / (1 - r * r));
  std::cout << "correlation of samples with relative deviation: r = " << r << " (t = " << tr << ")\n";
  EXPECT_GT(tr, studentCritical(2 * Alpha, n - 2));  // one-sided
}

// 64×64 pixels (16 tiles) on 1 and 4 threads, with a low-discrepancy
// sampler for the image and the deciding half's own stream.
TEST(AdaptiveSampling, SameSeedGivesTheSameImageWithOneAndFourThreads) {
  SceneFile sf = loadShippedScene("cornell-box", 64, 64, "sampler: {type: sobol}");
  RenderSpec spec{"path", "{}", 24, 3, 1};
  spec.adaptive = adaptive(4, 0.05);
  Image one = renderScene(sf, spec)->image();
  spec.threads = 4;
  Image four = renderScene(sf, spec)->image();
  EXPECT_EQ(one.pixels, four.pixels);
}

TEST(AdaptiveSampling, RefusesIntegratorsThatDoNotEstimatePixelByPixel) {
  SceneFile sf = loadShippedScene("cornell-box", 8, 8);
  for (auto [name, params] : {std::pair{"bdpt", "{}"}, std::pair{"guided", "{method: qlearning}"},
                              std::pair{"path", "{engine: wavefront}"}}) {
    RenderSpec spec{name, params, 8, 1};
    spec.adaptive = adaptive(4);
    EXPECT_THROW(renderScene(sf, spec), std::invalid_argument) << name;
  }
}

}  // namespace
}  // namespace lb::test
