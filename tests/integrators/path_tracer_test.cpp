// Path tracer against closed-form answers (t/z-tests, testing.md §2), its
// variants against each other (testing.md §3), determinism and scale
// invariance (§6, §7). Every bound comes from the film's measured variance.
#include <gtest/gtest.h>
#include <cstring>
#include "tests/support/render_helpers.h"

namespace lb::test {
namespace {

constexpr double Alpha = 0.01;

const std::vector<std::string> Variants = {
    "{sampling: bsdf, nee: false}",   "{sampling: cosine, nee: false}", "{sampling: uniform, nee: false}",
    "{nee: true, mis: none}",         "{nee: true, mis: balance}",      "{nee: true, mis: power}",
    "{sampling: cosine, nee: true, mis: power}"};

TEST(PathTracer, FurnaceGivesOneOverOneMinusAlbedo) {
  int tests = 2 * int(Variants.size());
  for (float a : {0.5f, 0.8f}) {
    SceneFile sf = loadSceneFromString(furnaceScene(a), "furnace.yaml");
    for (const auto& v : Variants) {
      std::string params = v.substr(0, v.size() - 1) + ", max_depth: -1}";
      auto film = renderScene(sf, {"path", params, 64, 3});
      EXPECT_TRUE(meanMatches(*film, 1 / (1 - a), Alpha / tests)) << "albedo " << a << " " << v;
      EXPECT_EQ(film->nonFiniteCount(), 0u);
    }
  }
}

TEST(PathTracer, WhiteFurnaceSphereInUniformEnvironment) {
  // An albedo-1 diffuse sphere under a uniform environment of radiance 1 is
  // invisible (L = 1); albedo 0.5 gives 0.5 on the sphere (a convex object
  // never sees itself).
  int tests = 2 * int(Variants.size());
  for (float a : {1.0f, 0.5f}) {
    std::string scene = "camera: {position: [0, 0, 4], look_at: [0, 0, 0], fov: 20}\n"
                        "film: {width: 16, height: 16}\n"
                        "materials: {m: {type: diffuse, albedo: " + std::to_string(a) + "}}\n"
                        "shapes: [{type: sphere, radius: 1, material: m}]\n"
                        "lights: [{type: environment, radiance: 1}]\n";
    SceneFile sf = loadSceneFromString(scene, "white-furnace.yaml");
    for (const auto& v : Variants) {
      auto film = renderScene(sf, {"path", v, 64, 5});
      // The central 6×6 pixels all see the sphere (its radius covers ~8 pixels).
      EXPECT_TRUE(meanMatches(*film, a, Alpha / tests, 1, 5, 5, 11, 11)) << "albedo " << a << " " << v;
    }
  }
}

TEST(PathTracer, PointLightOverDiffusePlaneIsAnalytic) {
  // L = ρ I cosθ / (π r²) at the plane point seen through each pixel; direct
  // light only (max_depth 2). The camera looks straight down, so the exact
  // value per pixel is computed from its ray.
  const float rho = 0.5f, I = 10.f, h = 2.f;
  SceneFile sf = loadSceneFromString(PointLightPlaneScene, "point-plane.yaml");
  auto film = renderScene(sf, {"path", "{max_depth: 2}", 32, 2});
  double exact = pointLightOverPlane(sf.scene->camera, Vec3(0.3f, h, 0.2f), I, rho);
  EXPECT_TRUE(meanMatches(*film, exact, Alpha));
}

TEST(PathTracer, VariantsAgreeOnCornellBox) {
  SceneFile sf = loadShippedScene("cornell-box", 32, 32);
  auto reference = regionMeans(*renderScene(sf, {"path", "{nee: true, mis: power}", 512, 100}), 4, 4);
  for (const auto& v : Variants) {
    auto film = renderScene(sf, {"path", v, 256, 7});
    EXPECT_EQ(compareRegions(regionMeans(*film, 4, 4), reference, Alpha / Variants.size()), "") << v;
  }
}

TEST(PathTracer, VariantsAgreeOnVeachMisScene) {
  SceneFile sf = loadShippedScene("veach-mis", 40, 25);
  auto reference = regionMeans(*renderScene(sf, {"path", "{nee: true, mis: power}", 1024, 100}), 4, 5);
  for (std::string v : {"{nee: false}", "{nee: true, mis: none}", "{nee: true, mis: balance}"}) {
    auto film = renderScene(sf, {"path", v, 1024, 9});
    EXPECT_EQ(compareRegions(regionMeans(*film, 4, 5), reference, Alpha / 3), "") << v;
  }
}

TEST(PathTracer, StratifiedAndIndependentSamplersAgree) {
  SceneFile sfInd = loadShippedScene("cornell-box", 32, 32);
  SceneFile sfStrat = loadShippedScene("cornell-box", 32, 32, "sampler: {type: stratified, strata: 4}");
  auto a = regionMeans(*renderScene(sfInd, {"path", "{}", 256, 1}), 4, 4);
  // The stratified film's per-pixel variance overestimates its true variance
  // (stratification only lowers it), so the test stays conservative.
  auto b = regionMeans(*renderScene(sfStrat, {"path", "{}", 256, 2}), 4, 4);
  EXPECT_EQ(compareRegions(a, b, Alpha), "");
}

TEST(PathTracer, SameSeedIsBitIdenticalWithOneAndTwoThreads) {
  SceneFile sf = loadShippedScene("cornell-box-spheres", 48, 48);
  for (std::string sampler : {"independent", "stratified"}) {
    SceneFile s = loadShippedScene("cornell-box-spheres", 48, 48, "sampler: {type: " + sampler + "}");
    Image one = renderScene(s, {"path", "{}", 8, 42, 1})->image();
    Image two = renderScene(s, {"path", "{}", 8, 42, 2})->image();
    ASSERT_EQ(one.pixels.size(), two.pixels.size());
    EXPECT_EQ(std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(Color)), 0) << sampler;
    Image other = renderScene(s, {"path", "{}", 8, 43, 2})->image();
    EXPECT_NE(std::memcmp(one.pixels.data(), other.pixels.data(), one.pixels.size() * sizeof(Color)), 0);
  }
}

TEST(PathTracer, ScaleSweepRendersTheSameImage) {
  // The same scene scaled by 1e-4 … 1e6, camera and lights included: ray
  // offsets derived from error bounds must neither leak nor self-intersect.
  const std::vector<std::string> scales = {"0.0001", "0.01", "100", "10000", "1000000"};
  for (std::string scene : {"cornell-box", "cornell-box-spheres"}) {
    SceneFile base = loadShippedScene(scene, 32, 32);
    auto reference = regionMeans(*renderScene(base, {"path", "{}", 256, 11}), 4, 4);
    for (const auto& s : scales) {
      SceneFile scaled = loadShippedScene(scene, 32, 32, "world_scale: " + s);
      auto film = renderScene(scaled, {"path", "{}", 256, 12});
      EXPECT_EQ(film->nonFiniteCount(), 0u);
      EXPECT_EQ(compareRegions(regionMeans(*film, 4, 4), reference, Alpha / (2 * scales.size())), "")
          << scene << " at scale " << s;
    }
  }
}

}  // namespace
}  // namespace lb::test
