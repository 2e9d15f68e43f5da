// The stress suite, part 1 (issue 7; README "Extremes"): every integrator
// against scale, tiny and hemisphere-filling lights, the 1/r² singularity and
// grazing light. The long versions are in experiments/extremes.yaml.
#include <gtest/gtest.h>
#include "core/scene_loader.h"
#include "tests/support/render_helpers.h"
#include "tests/support/repeats.h"
#include "tests/support/statistics.h"

namespace lb::test {
namespace {

constexpr double Alpha = 1e-3;

class Extremes : public ::testing::TestWithParam<IntegratorUnderTest> {};

TEST(StudentCritical, MatchesTables) {
  EXPECT_NEAR(studentCritical(0.05, 10), 2.228, 1e-3);
  EXPECT_NEAR(studentCritical(0.01, 3), 5.841, 1e-3);
  EXPECT_NEAR(studentCritical(0.05, 1e6), 1.960, 1e-3);
}

// The Cornell box and the glass-sphere caustic scaled by 1e-4 … 1e6 (camera,
// lights and radii included; photon radii, SPPM radii and cache spacing are
// relative to the scene by default) give the same image as at scale 1: five
// seeds per scale, region means compared by Welch t-tests on the seeds' spread
// (which includes photon-map and cache noise frozen into each run).
TEST_P(Extremes, ScaleDoesNotChangeTheImage) {
  const IntegratorUnderTest& it = GetParam();
  const int Seeds = 5;
  for (auto [scene, w, h] : {std::tuple{"cornell-box", 16, 16}, std::tuple{"caustic-glass-sphere", 16, 12}}) {
    SeedMeans unit = seedMeans(loadShippedScene(scene, w, h), it, Seeds, 2, 2, 100);
    EXPECT_EQ(unit.nonFinite, 0u);
    for (const char* scale : {"1e-4", "1e-2", "1e2", "1e4", "1e6"}) {
      SeedMeans scaled = seedMeans(loadShippedScene(scene, w, h, std::string("world_scale: ") + scale), it, Seeds, 2, 2, 200);
      EXPECT_EQ(scaled.nonFinite, 0u) << scene << " at scale " << scale;
      std::string failures = compareSeedMeans(scaled, unit, Alpha, 5 * 12);
      EXPECT_TRUE(failures.empty()) << scene << " at scale " << scale << ":" << failures;
    }
  }
}

// A spherical light of radius 1e-1 … 1e-6 (of its height above the plane)
// emitting 10/(πr²) is, by the shell theorem, exactly the point light of
// intensity 10: every integrator must match the analytic image. The scene has
// no indirect light (a single plane), so each integrator's film variance
// covers all its noise.
TEST_P(Extremes, TinySphereLightsMatchThePointLight) {
  const IntegratorUnderTest& it = GetParam();
  for (int e = 1; e <= 6; ++e) {
    SceneFile sf = loadShippedScene("extremes/tiny-light-1e-" + std::to_string(e), 16, 16);
    Rendered r = renderWith(sf, it, 7, "{}", 4 * it.spp);
    EXPECT_EQ(r.report.nonFinite, 0u) << "radius 1e-" << e;
    double exact = pointLightOverPlane(sf.scene->camera, Vec3(1.6f, 1, 0.2f), 10, 0.5f);
    EXPECT_TRUE(meanMatches(*r.film, exact, sidak(Alpha, 6))) << "radius 1e-" << e;
  }
}

// A light filling every direction: inside a closed sphere of albedo 0.5
// emitting 1, L = 1/(1 − 0.5) = 2 everywhere (furnace.yaml). 16 independent
// seeds, so the Student-t critical value (15 dof) is 4.6 at this level rather
// than 18.7 with 3 dof; light tracing, whose furnace variance per sample is
// ~45× the path tracer's, gets 8× the samples. The bound's half-width must
// then resolve a 2 % error, or the test could not catch one.
TEST_P(Extremes, HemisphereFillingLightGivesTheFurnaceValue) {
  IntegratorUnderTest it = GetParam();
  if (it.name == "light") it.spp *= 8;
  const int Seeds = 16;
  SeedMeans m = seedMeans(loadShippedScene("extremes/furnace", 16, 16), it, Seeds, 1, 1, 300);
  EXPECT_EQ(m.nonFinite, 0u);
  SeedMeans exact;
  exact.seeds = Seeds;
  exact.regions.mean.assign(3, 2.0);
  exact.regions.varianceOfMean.assign(3, 0.0);
  std::string failures = compareSeedMeans(m, exact, Alpha, 3);
  EXPECT_TRUE(failures.empty()) << failures;
  double critical = studentCritical(sidak(Alpha, 3), Seeds - 1);
  for (int c = 0; c < 3; ++c)
    EXPECT_LE(critical * std::sqrt(m.regions.varianceOfMean[size_t(c)]), 0.02 * 2.0)
        << "channel " << c << ": the bound is too wide to catch a 2 % error";
}

// The 1/r² singularity: a light 1e-6 above a diffuse plane. Nothing may turn
// into Inf/NaN; the per-pixel variance shows the cost.
TEST_P(Extremes, TouchingLightStaysFinite) {
  const IntegratorUnderTest& it = GetParam();
  SceneFile sf = loadShippedScene("extremes/touching-light", 16, 16);
  Rendered r = renderWith(sf, it, 11);
  EXPECT_EQ(r.report.nonFinite, 0u);
  Image img = r.film->image();
  double maxValue = 0;
  for (const Color& c : img.pixels) {
    ASSERT_TRUE(isFinite(c));
    maxValue = std::max(maxValue, double(maxComponent(c)));
  }
  std::cerr << it.name << ": touching light, largest pixel " << maxValue << ", mean variance of the pixel means "
            << r.film->meanVarianceOfMean() << "\n";
}

// Light at 89.9° from the normal: L = ρ/π · E cos(89.9°) on the whole plane.
// Light tracing is the documented exception: a directional light emits from a
// disc covering the scene's bounding sphere, and at 89.9° only ~1e-5 of its
// particles land in view, so at test budgets its image is empty (unbiased,
// but hopeless); it must still be finite.
TEST_P(Extremes, GrazingLightMatchesCosine) {
  const IntegratorUnderTest& it = GetParam();
  SceneFile sf = loadShippedScene("extremes/grazing-light", 16, 16);
  Rendered r = renderWith(sf, it, 13);
  EXPECT_EQ(r.report.nonFinite, 0u);
  double exact = 0.5 / Pi * 1000 * 0.0017453284;
  if (it.name == "light") {
    std::cerr << "light: grazing directional light, documented limitation: image mean " << regionMeans(*r.film, 1, 1).mean[0]
              << " vs " << exact << " (~1e-5 of the particles land in view)\n";
    return;
  }
  EXPECT_TRUE(meanMatches(*r.film, exact, Alpha));
}

INSTANTIATE_TEST_SUITE_P(AllIntegrators, Extremes, ::testing::ValuesIn(fastIntegrators()), integratorTestName);

}  // namespace
}  // namespace lb::test
