// Manifold next-event estimation in the path tracer (`mnee: true`,
// integrators/path_estimator/manifold_nee.cpp):
//  * under a flat water surface every floor point has exactly one refracted
//    path to a light point, so MNEE is unbiased there: seen from inside the
//    water (L S D E, which BDPT renders by connecting light subpaths to the
//    camera, an estimator that shares nothing with MNEE), its region means
//    equal BDPT's within the seeds' spread, under a point light (which only
//    MNEE reaches among the path tracer's strategies) and under an area
//    light (where BSDF sampling also reaches it, so its hits must count
//    zero or the light would count twice); and under a glass slab, where
//    the chains have two refractions and again one solution;
//  * under a glass sphere, where a caustic's point has several refracted
//    paths to the light, MNEE is darker: the bias of the solutions its seed
//    does not lead to;
//  * specular manifold sampling (`sms: unbiased`) agrees with BDPT under the
//    flat water and the slab too, and through a flat mirror;
//  * the same seed gives the same image with one thread or two;
//  * refusals.
// Seen failing with the contribution times 1.05 (the comparison's own check
// below) and with BSDF sampling's hits of the light counted as well.
// The solver itself: specular_chain_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include "core/error.h"
#include "tests/support/consistent_helpers.h"
#include "tests/support/render_helpers.h"

namespace lb::test {
namespace {

constexpr double Alpha = 1e-3;

// Water (IOR 1.33) fills the space below y = 0 above a floor at y = −1; the
// camera is in the water, the light above it.
std::string flatWater(const std::string& light) {
  return "camera: {position: [0, -0.3, 1.6], look_at: [0, -1, -0.2], fov: 45}\n"
         "film: {width: 64, height: 48}\n"
         "materials: {floor: {type: diffuse, albedo: 0.8}, water: {type: dielectric, ior: 1.33}}\n"
         "shapes:\n"
         "  - {type: rectangle, material: floor, transform: {scale: 3, rotate_x: -90, translate: [0, -1, 0]}}\n"
         "  - {type: rectangle, material: water, transform: {scale: 3, rotate_x: -90}}\n" +
         light;
}

const std::string PointLight = "lights: [{type: point, position: [0.5, 1.5, -0.3], intensity: 6}]\n";
const std::string AreaLight =
    "  - {type: rectangle, material: none, emission: 60, transform: {scale: 0.2, rotate_x: 90, "
    "translate: [0.5, 1.5, -0.3]}}\n";

// A slab of glass (0.2 thick) above a floor, the camera below it: chains of
// two refractions, again with one solution. The slab reaches past the floor:
// light leaving through its side faces would land on floor points that also
// receive it through the bottom face, a second solution (with a slab as wide
// as the floor, MNEE is 10 % darker in the middle of the image).
const std::string GlassSlab =
    "camera: {position: [0, -0.5, 2.6], look_at: [0, -1, 0], fov: 45}\n"
    "film: {width: 64, height: 48}\n"
    "materials: {floor: {type: diffuse, albedo: 0.8}, glass: {type: dielectric, ior: 1.5}}\n"
    "shapes:\n"
    "  - {type: rectangle, material: floor, transform: {scale: 3, rotate_x: -90, translate: [0, -1, 0]}}\n"
    "  - {type: box, material: glass, transform: {scale: [4, 0.1, 4]}}\n"
    "lights: [{type: point, position: [0.3, 1.5, -0.2], intensity: 6}]\n";

TEST(Mnee, UnderFlatWaterOrGlassItRendersBdptsMeans) {
  const int Seeds = 8, Regions = 3;
  for (const auto& [name, text] : {std::pair<std::string, std::string>{"point light", flatWater(PointLight)},
                                   std::pair<std::string, std::string>{"area light", flatWater(AreaLight)},
                                   std::pair<std::string, std::string>{"glass slab", GlassSlab}}) {
    SceneFile scene = loadSceneFromString(text, "flat-water.yaml");
    std::vector<bool> floor = diffusePrimaryHits(*scene.scene);
    ASSERT_GT(countTrue(floor), 1500u) << name;
    SeedMeans bdpt = maskedSeedMeans(scene, {"bdpt", "{}", 64, 91}, Seeds, Regions, floor);
    // sms too (its seeds cost a Newton solve each, so not under the area
    // light, whose BSDF hits are MNEE's test and sms's by the same code).
    std::vector<std::pair<std::string, uint64_t>> methods = {{"{mnee: true}", 64}};
    if (name != "area light") methods.push_back({"{sms: unbiased, sms_trials: 1000}", name == "glass slab" ? 96 : 32});
    for (const auto& [params, spp] : methods) {
      SeedMeans mnee = maskedSeedMeans(scene, {"path", params, spp, 11}, Seeds, Regions, floor);
      EXPECT_EQ(mnee.nonFinite, 0u);
      const int comparisons = Regions * Regions * 3;
      std::string failures = compareSeedMeans(mnee, bdpt, Alpha, comparisons);
      EXPECT_TRUE(failures.empty()) << name << ", " << params << ":" << failures;
      EXPECT_FALSE(compareSeedMeans(scaled(mnee, 1.05), bdpt, Alpha, comparisons).empty()) << name << ", " << params;
    }
  }
}

// Under a glass sphere the refracted paths from the light to a floor point
// of the caustic's outer ring are several (rays through the sphere's rim
// cross those through its middle before they reach the floor); Newton's
// method finds the one its straight seed leads to (or none, near the fold
// where it may not converge) and the others are lost. So MNEE's caustic is
// darker than BDPT's by more than the noise: the bias the documentation
// states (measured: 43 % on the caustic's brightest pixels, 10 sigma).
// Specular manifold sampling, unbiased, finds them all and agrees with BDPT.
TEST(Mnee, UnderAGlassSphereItLosesTheOtherSolutions) {
  const int Seeds = 8;
  SceneFile scene = loadShippedScene("glass-sphere-point", 128, 96);
  std::vector<bool> diffuse = diffusePrimaryHits(*scene.scene);
  std::vector<bool> caustic = causticPixels(scene, {"light", "{}", 256, 700}, diffuse);
  ASSERT_GE(countTrue(caustic), 4u);
  const RenderSpec mnee{"path", "{mnee: true}", 64, 11}, bdpt{"bdpt", "{}", 64, 91};
  SeedMeans a = maskedSeedMeans(scene, mnee, Seeds, 1, caustic), b = maskedSeedMeans(scene, bdpt, Seeds, 1, caustic);
  double deficit = b.regions.mean[1] - a.regions.mean[1];
  double sigma = std::sqrt(a.regions.varianceOfMean[1] + b.regions.varianceOfMean[1]);
  std::printf("caustic (%zu pixels): MNEE %.4f, BDPT %.4f: %.1f %% lower, %.1f sigma\n", countTrue(caustic),
              a.regions.mean[1], b.regions.mean[1], 100 * deficit / b.regions.mean[1], deficit / sigma);
  EXPECT_GT(deficit, 4 * sigma);
  // Unbiased SMS, whose seeds reach every solution, restores it.
  SeedMeans c = maskedSeedMeans(scene, {"path", "{sms: unbiased, sms_trials: 1000}", 32, 21}, Seeds, 1, caustic);
  std::string failures = compareSeedMeans(c, b, Alpha, 3);
  EXPECT_TRUE(failures.empty()) << "sms:" << failures;
  std::printf("caustic: SMS %.4f\n", c.regions.mean[1]);
}

// Specular manifold sampling through a mirror: a floor lit by a point light
// directly and by its image in a flat mirror (one solution), which plain
// path tracing cannot reach (the light cannot be hit) and BDPT renders by
// connecting light subpaths to the camera.
TEST(Mnee, SmsThroughAMirrorRendersBdptsMeans) {
  const int Seeds = 8, Regions = 3;
  SceneFile scene = loadSceneFromString(
      "camera: {position: [0, 2.5, 3], look_at: [0, 0, -0.3], fov: 45}\n"
      "film: {width: 64, height: 48}\n"
      "materials: {floor: {type: diffuse, albedo: 0.8}, mirror: {type: conductor}}\n"
      "shapes:\n"
      "  - {type: rectangle, material: floor, transform: {scale: 3, rotate_x: -90}}\n"
      "  - {type: rectangle, material: mirror, transform: {scale: 1, translate: [0, 0.5, -1]}}\n"
      "lights: [{type: point, position: [0.5, 1.5, 0.5], intensity: 4}]\n",
      "mirror.yaml");
  std::vector<bool> floor = diffusePrimaryHits(*scene.scene);
  ASSERT_GT(countTrue(floor), 1500u);
  SeedMeans sms = maskedSeedMeans(scene, {"path", "{sms: unbiased, sms_trials: 1000}", 32, 11}, Seeds, Regions, floor);
  SeedMeans bdpt = maskedSeedMeans(scene, {"bdpt", "{}", 64, 91}, Seeds, Regions, floor);
  const int comparisons = Regions * Regions * 3;
  std::string failures = compareSeedMeans(sms, bdpt, Alpha, comparisons);
  EXPECT_TRUE(failures.empty()) << failures;
  EXPECT_FALSE(compareSeedMeans(scaled(sms, 1.05), bdpt, Alpha, comparisons).empty());
}

TEST(Mnee, SameImageWithOneThreadOrTwo) {
  SceneFile scene = loadSceneFromString(flatWater(AreaLight), "flat-water.yaml");
  for (const char* params : {"{mnee: true}", "{sms: unbiased}", "{sms: biased, sms_trials: 4}"}) {
    RenderSpec spec{"path", params, 4, 5, 1};
    Image one = renderScene(scene, spec)->image();
    spec.threads = 2;
    EXPECT_EQ(one.pixels, renderScene(scene, spec)->image().pixels) << params;
  }
}

TEST(Mnee, RefusesWhatItCannotHonour) {
  SceneFile scene = loadShippedScene("cornell-box", 8, 8);
  for (const char* params : {"{mnee: true, nee: false}", "{mnee: true, engine: wavefront}",
                             "{mnee: true, regularize: true}", "{mnee: true, mnee_max_chain: 3}",
                             "{mnee: true, sms: unbiased}", "{sms: biased, nee: false}", "{sms: unbiased, sms_trials: 0}",
                             "{sms: unbiased, mnee_max_chain: 2}", "{mnee: true, mis: variance_aware}"})
    EXPECT_THROW(renderScene(scene, {"path", params, 1, 1}), ConfigError) << params;
  // guided draws its own directions and reads no manifold keys.
  EXPECT_THROW(renderScene(scene, {"guided", "{mnee: true}", 1, 1}), ConfigError);
}

}  // namespace
}  // namespace lb::test
