// The `direct_optimal` integrator (integrators/direct_optimal/): direct
// lighting with optimal MIS must estimate what `direct` does, region by
// region within the measured noise, whether α is learned (`mis: optimal`)
// or zero (`mis: balance`); its learning leaves the image independent of the
// thread count; and it refuses what cannot learn per pixel.
#include <gtest/gtest.h>
#include <cstring>
#include "tests/support/render_helpers.h"

namespace lb::test {
namespace {

void expectAgreesWithDirect(const SceneFile& sf, uint64_t spp, int regions) {
  auto reference = regionMeans(*renderScene(sf, {"direct", "{}", 2 * spp, 1}), regions, regions);
  for (const char* params : {"{mis: optimal, pilot_passes: 2}", "{mis: balance}"}) {
    auto film = renderScene(sf, {"direct_optimal", params, spp, 2});
    EXPECT_EQ(film->nonFiniteCount(), 0u) << params;
    EXPECT_EQ(compareRegions(regionMeans(*film, regions, regions), reference, 1e-3), "") << params;
  }
}

// Diffuse walls under a large light, a mirror and a glass sphere (delta
// lobes, outside the combination), and the spheres' shadows (occluded light
// samples, where the BSDF technique's density is 0 in path space).
TEST(DirectOptimal, AgreesWithDirectInTheCornellBoxWithSpheres) {
  expectAgreesWithDirect(loadShippedScene("cornell-box-spheres", 32, 32), 1024, 4);
}

// Veach's plates and lights of four sizes: where each technique wins
// somewhere, and α is far from zero.
TEST(DirectOptimal, AgreesWithDirectOnVeachsMisScene) {
  expectAgreesWithDirect(loadShippedScene("external/veach-mis/scene.xml", 48, 32), 2048, 4);
}

// An importance-sampled environment map over a glossy copper sphere (the
// light technique's density where BSDF samples escape), and a point light
// (a delta light: its samples outside the combination).
TEST(DirectOptimal, AgreesWithDirectUnderAnEnvironmentMapAndAPointLight) {
  expectAgreesWithDirect(loadShippedScene("env-glossy", 32, 20), 1024, 4);
  expectAgreesWithDirect(loadShippedScene("point-light", 32, 24), 256, 4);
}

// Two environment lights (a direction at infinity is both's: a light sample
// from one must carry the other's radiance and density too) over a coated
// conductor, whose pdf is an estimate (layered.h: α stays 0 there).
TEST(DirectOptimal, AgreesWithDirectUnderTwoEnvironmentsAndACoating) {
  expectAgreesWithDirect(
      loadShippedScene("env-glossy", 32, 20,
                       "lights: [{type: environment, file: maps/sky.exr, rotate_y: 40, sampling: importance},\n"
                       "         {type: environment, radiance: [0.4, 0.3, 0.2]}]\n"
                       "materials: {copper: {type: coated_conductor, roughness: 0.2}, floor: {type: diffuse, albedo: 0.6}}"),
      1024, 4);
}

// A pixel's α depends on its earlier samples, all from the thread that owns
// its tile: bit-identical at one and two threads, and different from α = 0.
TEST(DirectOptimal, SameSeedIsBitIdenticalWithOneAndTwoThreads) {
  SceneFile s = loadShippedScene("veach-mis", 32, 20);
  Image one = renderScene(s, {"direct_optimal", "{pilot_passes: 2}", 8, 42, 1})->image();
  Image two = renderScene(s, {"direct_optimal", "{pilot_passes: 2}", 8, 42, 2})->image();
  ASSERT_EQ(one.pixels.size(), two.pixels.size());
  EXPECT_EQ(std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(Color)), 0);
  Image balance = renderScene(s, {"direct_optimal", "{mis: balance}", 8, 42, 1})->image();
  EXPECT_NE(std::memcmp(one.pixels.data(), balance.pixels.data(), one.pixels.size() * sizeof(Color)), 0);
}

TEST(DirectOptimal, RefusesWhatCannotLearnPerPixel) {
  SceneFile scene = loadShippedScene("cornell-box", 8, 8);
  EXPECT_THROW(renderScene(scene, {"direct_optimal", "{pilot_passes: -1}", 1, 1}), ConfigError);
  EXPECT_THROW(renderScene(scene, {"direct_optimal", "{mis: power}", 1, 1}), ConfigError);
  SceneFile sobol = loadShippedScene("cornell-box", 8, 8, "sampler: {type: sobol}");
  EXPECT_ANY_THROW(renderScene(sobol, {"direct_optimal", "{}", 1, 1}));
  EXPECT_NO_THROW(renderScene(sobol, {"direct_optimal", "{mis: balance}", 1, 1}));
  RenderSpec adaptive{"direct_optimal", "{}", 4, 1};
  adaptive.adaptive.enabled = true;
  EXPECT_ANY_THROW(renderScene(scene, adaptive));
}

}  // namespace
}  // namespace lb::test
