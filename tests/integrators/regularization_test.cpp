// Path-space regularization in the path tracer, BDPT and VCM
// (core/bsdfs/regularization.h):
//  * the schedule is α_0 (k + 1)^(−λ), as documented;
//  * where no delta vertex follows a non-delta one (the Cornell box) the
//    image is the unregularized one, bit for bit; where one does (the glass
//    sphere's caustic) it is not;
//  * at a fixed roughness α the regularized path tracer and the regularized
//    BDPT compute exactly the scene whose glass is rough (GGX, α) after the
//    first diffuse vertex: on the pixels whose camera ray first meets a
//    diffuse surface, their region means equal plain BDPT's on that scene
//    (an estimator of the rough scene that knows nothing of twins), within
//    the seeds' spread;
//  * where the camera sees the floor through water (L S D S E, the case
//    regularization is for: the water next to the camera stays smooth, the
//    water next to the light is rough), regularized BDPT's region means equal
//    the regularized path tracer's — two estimators written apart, one
//    mollifying by its walk's prefix and next-event estimation, the other by
//    the path rule its light subpaths and t = 1 strategy follow;
//  * so do VCM's merges (modes vcm and bpm), which join a regularized light
//    subpath at a camera vertex;
//  * each image is the same with one thread or two; refusals.
// The bias against the true (smooth) scene, and that it shrinks with α, is
// tested with the other consistent methods (consistent_caustic_test.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <tuple>
#include "core/error.h"
#include "core/bsdfs/dielectric.h"
#include "core/bsdfs/regularization.h"
#include "tests/support/consistent_helpers.h"
#include "tests/support/render_helpers.h"

namespace lb::test {
namespace {

constexpr double Alpha = 1e-3;

TEST(Regularization, RoughnessFollowsTheSchedule) {
  RegularizationSettings s;
  s.initialRoughness = 0.2f;
  s.exponent = 1.f / 6.f;
  for (uint64_t k : {0ull, 1ull, 7ull, 63ull, 999ull})
    EXPECT_NEAR(s.roughness(k), 0.2 * std::pow(double(k) + 1, -1.0 / 6.0), 1e-6) << k;
  s.exponent = 0;
  EXPECT_EQ(s.roughness(0), s.roughness(12345));
}

// An index-matched interface bends nothing and the rough model cannot
// represent it (its half-vector vanishes for straight transmission): it
// keeps no twin, rather than one that transmits nothing.
TEST(Regularization, AnIndexMatchedInterfaceHasNoTwin) {
  EXPECT_EQ(SmoothDielectric(1.f).mollified(0.1f), nullptr);
  EXPECT_NE(SmoothDielectric(1.33f).mollified(0.1f), nullptr);
}

TEST(Regularization, ChangesOnlyPathsWithADeltaVertexAfterANonDeltaOne) {
  SceneFile cornell = loadShippedScene("cornell-box", 32, 32);
  Image plain = renderScene(cornell, {"path", "{}", 8, 3})->image();
  Image regular = renderScene(cornell, {"path", "{regularize: true}", 8, 3})->image();
  EXPECT_EQ(plain.pixels, regular.pixels);
  SceneFile glass = loadShippedScene("caustic-glass-sphere", 32, 24);
  EXPECT_NE(renderScene(glass, {"path", "{}", 8, 3})->image().pixels,
            renderScene(glass, {"path", "{regularize: true}", 8, 3})->image().pixels);
  EXPECT_EQ(renderScene(cornell, {"bdpt", "{}", 4, 3})->image().pixels,
            renderScene(cornell, {"bdpt", "{regularize: true}", 4, 3})->image().pixels);
  EXPECT_NE(renderScene(glass, {"bdpt", "{}", 4, 3})->image().pixels,
            renderScene(glass, {"bdpt", "{regularize: true}", 4, 3})->image().pixels);
  EXPECT_EQ(renderScene(cornell, {"vcm", "{}", 4, 3})->image().pixels,
            renderScene(cornell, {"vcm", "{regularize: true}", 4, 3})->image().pixels);
  EXPECT_NE(renderScene(glass, {"vcm", "{}", 4, 3})->image().pixels,
            renderScene(glass, {"vcm", "{regularize: true}", 4, 3})->image().pixels);
}

// α = 0.2, fixed: 2 × 2 regions of the pixels whose camera ray first meets
// a diffuse surface, and the rough caustic's own pixels (chosen on an
// independent light-tracing render of the rough scene), where the roughness
// shapes the mean. Seen failing when a regularized vertex's throughput is
// scaled by 1.05 and when the twins' roughness is 1.3 α (path); for BDPT
// when its light subpaths regularize only after a non-delta vertex, as its
// camera subpaths do (the caustic is then the smooth sphere's).
// VCM in mode bpt shares bdpt's walks but drives them itself (its own
// light subpath per pixel, t = 1 splatted as it goes).
struct RegularizedEstimator {
  const char *name, *integrator, *params;
  int spp;
};

class RegularizedRoughScene : public ::testing::TestWithParam<RegularizedEstimator> {};

TEST_P(RegularizedRoughScene, AtAFixedRoughnessItRendersTheRoughScene) {
  const int Seeds = 8, Regions = 2;
  const RegularizedEstimator& e = GetParam();
  SceneFile smooth = loadShippedScene("caustic-glass-sphere", 128, 96);
  SceneFile rough = loadShippedScene("caustic-glass-sphere", 128, 96,
                                     "materials: {floor: {type: diffuse, albedo: 0.7}, "
                                     "glass: {type: dielectric, ior: 1.5, roughness: 0.2}}");
  const RenderSpec regularize{
      e.integrator, std::string("{regularize: true, regularize_roughness: 0.2, regularize_exponent: 0") + e.params + "}",
      uint64_t(e.spp), 40};
  const RenderSpec bdpt{"bdpt", "{}", 64, 90};
  std::vector<bool> diffuse = diffusePrimaryHits(*smooth.scene);
  std::vector<bool> caustic = causticPixels(rough, {"light", "{}", 256, 700}, diffuse);
  ASSERT_GT(countTrue(diffuse), 1000u);
  ASSERT_GE(countTrue(caustic), 4u);
  for (const auto& [name, mask, regions] :
       {std::make_tuple("diffuse", &diffuse, Regions), std::make_tuple("caustic", &caustic, 1)}) {
    SeedMeans a = maskedSeedMeans(smooth, regularize, Seeds, regions, *mask);
    SeedMeans b = maskedSeedMeans(rough, bdpt, Seeds, regions, *mask);
    EXPECT_EQ(a.nonFinite, 0u);
    const int comparisons = 2 * regions * regions * 3;
    std::string failures = compareSeedMeans(a, b, Alpha, comparisons);
    EXPECT_TRUE(failures.empty()) << name << ":" << failures;
    // … and the comparison can see a 5 % error.
    EXPECT_FALSE(compareSeedMeans(scaled(a, 1.05), b, Alpha, comparisons).empty()) << name;
  }
}

INSTANTIATE_TEST_SUITE_P(Regularization, RegularizedRoughScene,
                         ::testing::Values(RegularizedEstimator{"path", "path", "", 256},
                                           RegularizedEstimator{"bdpt", "bdpt", "", 192},
                                           RegularizedEstimator{"vcm_bpt", "vcm", ", mode: bpt", 192}),
                         [](const auto& info) { return std::string(info.param.name); });

// The camera above flat water (IOR 1.33) looking down at the floor beneath
// it, a point light above: the floor's light has crossed the water twice
// (L S D S E), which neither estimator reaches unregularized.
const std::string WaterSeenFromAbove =
    "camera: {position: [0, 0.9, 1.6], look_at: [0, -1, -0.2], fov: 40}\n"
    "film: {width: 48, height: 36}\n"
    "materials: {floor: {type: diffuse, albedo: 0.8}, water: {type: dielectric, ior: 1.33}}\n"
    "shapes:\n"
    "  - {type: rectangle, material: floor, transform: {scale: 3, rotate_x: -90, translate: [0, -1, 0]}}\n"
    "  - {type: rectangle, material: water, transform: {scale: 3, rotate_x: -90}}\n"
    "lights: [{type: point, position: [0.5, 1.5, -0.3], intensity: 6}]\n";

// α = 0.3 fixed, the pixels that see the water as one region. BDPT's seed
// means are heavy-tailed here (the twin's peaked lobe in connections): at
// α = 0.2 two sets of 16 seeds read 2.2 % below the path tracer at 3.5 σ of
// their spread and a third agreed, while two long renders (8192 spp against
// 16384) agreed within 0.4 %; at α = 0.3 the long renders agree within
// 0.01 % and this test reads BDPT 1.5 % low, within its bound. What it can
// resolve: that BDPT reaches L S D S E with the right mean, and a 5 % error
// (below). It does not resolve the t = 1 rule (letting t = 1 end at a
// regularized vertex moves the mean by 1.5 %; the black-floor test below
// does), nor light subpaths that
// regularize only after a non-delta vertex (−0.2 %: MIS gives the path
// tracer's strategy, s = 1, 99 % of the weight here); the rough-scene test
// above fails on the latter (its caustic 25 % too bright).
TEST(Regularization, BdptSeesTheFloorThroughWaterAsThePathTracerDoes) {
  const int Seeds = 16, Regions = 1;
  SceneFile scene = loadSceneFromString(WaterSeenFromAbove, "water-from-above.yaml");
  std::vector<bool> water = primaryHitMask(
      *scene.scene, [](bool hit, const SurfaceInteraction& si) { return hit && si.material && si.material->isDelta(); });
  ASSERT_GT(countTrue(water), 1000u);
  const std::string params = "{regularize: true, regularize_roughness: 0.3, regularize_exponent: 0}";
  SeedMeans bdpt = maskedSeedMeans(scene, {"bdpt", params, 128, 21}, 2 * Seeds, Regions, water);
  SeedMeans path = maskedSeedMeans(scene, {"path", params, 1024, 61}, Seeds, Regions, water);
  const int comparisons = Regions * Regions * 3;
  EXPECT_EQ(bdpt.nonFinite, 0u);
  std::string failures = compareSeedMeans(bdpt, path, Alpha, comparisons);
  EXPECT_TRUE(failures.empty()) << failures;
  EXPECT_FALSE(compareSeedMeans(scaled(bdpt, 1.05), path, Alpha, comparisons).empty());
  // Unregularized, BDPT does not reach the floor through the water at all.
  double unregularized = maskedSeedMeans(scene, {"bdpt", "{}", 16, 21}, 2, 1, water).regions.mean[1];
  double all = 0;
  for (double m : path.regions.mean) all += m;
  EXPECT_LT(unregularized, 0.01 * all / double(path.regions.mean.size()));
}

// VCM sees that floor through merges too (unregularized it already does:
// a photon crosses the smooth water, the camera subpath meets the floor
// through it and merges there). Regularized, its light subpaths cross the
// rough twin and a merge at the floor must weigh the connections that the
// twin now allows: modes vcm (all strategies) and bpm (merges and s = 0
// only) against the regularized path tracer. The merges' bias is the
// kernel's on the floor's irradiance, smooth here (point light 2.5 above the
// floor, through flat water): for a disc of radius r about (r/ℓ)²/8 relative
// with ℓ ≳ 1 the scale it varies on, under 0.2 % at r = 0.1 (fixed, α = 1),
// below what 16 seeds resolve; no allowance is added. Seen failing, both
// modes, when VCM's camera subpaths do not regularize (−5 to −6 %: the
// weights then miss the strategies through the camera's twin), when its
// light subpaths do not (+5 to +7 %; vcm_bpt above fails too, its caustic
// 24 % bright), and when scaled by 1.05.
TEST(Regularization, VcmSeesTheFloorThroughWaterAsThePathTracerDoes) {
  const int Seeds = 16, Regions = 1;
  SceneFile scene = loadSceneFromString(WaterSeenFromAbove, "water-from-above.yaml");
  std::vector<bool> water = primaryHitMask(
      *scene.scene, [](bool hit, const SurfaceInteraction& si) { return hit && si.material && si.material->isDelta(); });
  const std::string params = "regularize: true, regularize_roughness: 0.3, regularize_exponent: 0";
  SeedMeans path = maskedSeedMeans(scene, {"path", "{" + params + "}", 1024, 61}, Seeds, Regions, water);
  const int comparisons = Regions * Regions * 3;
  for (const char* mode : {"vcm", "bpm"}) {
    SeedMeans vcm = maskedSeedMeans(
        scene, {"vcm", "{" + params + ", mode: " + mode + ", radius: 0.1, alpha: 1}", 128, 33}, Seeds, Regions, water);
    EXPECT_EQ(vcm.nonFinite, 0u) << mode;
    std::string failures = compareSeedMeans(vcm, path, Alpha, comparisons);
    EXPECT_TRUE(failures.empty()) << mode << failures;
    EXPECT_FALSE(compareSeedMeans(scaled(vcm, 1.05), path, Alpha, comparisons).empty()) << mode;
  }
}

// The same water over a black floor: every path that reaches the camera
// meets the smooth water first and then either the black floor or nothing,
// so the regularized image is exactly black. A light subpath regularizes
// the water too, and connecting its rough twin to the camera (t = 1) would
// paint the light's glossy reflection on it: this is the rule that forbids
// it (seen failing without it: the highlight sums to 0.15 over the image).
TEST(Regularization, BdptNeverConnectsARegularizedVertexToTheCamera) {
  std::string text = WaterSeenFromAbove;
  text.replace(text.find("albedo: 0.8"), 11, "albedo: 0.0");
  SceneFile scene = loadSceneFromString(text, "water-over-black.yaml");
  for (const char* integrator : {"bdpt", "path", "vcm"}) {
    Image image = renderScene(scene, {integrator, "{regularize: true, regularize_roughness: 0.3}", 16, 7})->image();
    double sum = 0;
    for (const Color& c : image.pixels) sum += double(c.r) + c.g + c.b;
    EXPECT_EQ(sum, 0.0) << integrator;
  }
}

TEST(Regularization, SameImageWithOneThreadOrTwo) {
  SceneFile scene = loadSceneFromString(WaterSeenFromAbove, "water-from-above.yaml");
  for (const char* integrator : {"path", "bdpt", "vcm"}) {
    RenderSpec spec{integrator, "{regularize: true}", 4, 5, 1};
    Image one = renderScene(scene, spec)->image();
    spec.threads = 2;
    EXPECT_EQ(one.pixels, renderScene(scene, spec)->image().pixels) << integrator;
  }
}

TEST(Regularization, RefusesWhatItCannotHonour) {
  SceneFile scene = loadShippedScene("cornell-box", 8, 8);
  for (const auto& [integrator, params] : std::vector<std::pair<std::string, std::string>>{
           {"path", "{regularize: true, engine: wavefront}"},
           {"path", "{regularize: true, sampling: cosine}"},
           {"path", "{regularize_roughness: 0.2}"},  // a key of regularize: true only
           {"path", "{regularize: true, regularize_exponent: 0.5}"},  // not consistent
           {"guided", "{regularize: true}"},
           {"bdpt", "{regularize_roughness: 0.2}"},
           {"bdpt", "{regularize: true, regularize_exponent: 0.5}"},
           {"vcm", "{regularize_roughness: 0.2}"},
           {"vcm", "{regularize: true, regularize_exponent: 0.5}"},
       })
    EXPECT_THROW(renderScene(scene, {integrator, params, 1, 1}), ConfigError) << integrator << " " << params;
  RenderSpec adaptive{"path", "{regularize: true}", 4, 1};
  adaptive.adaptive.enabled = true;
  EXPECT_ANY_THROW(renderScene(scene, adaptive));
}

}  // namespace
}  // namespace lb::test
