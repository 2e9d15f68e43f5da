// Photon mapping and SPPM against the path tracer (testing.md §3, §5) where
// issue 11 found them wrong: a glossy sphere in an environment (the
// BSDF-sampled half of the environment's direct light), the Cornell box with
// spheres at equal max_depth (one path-length rule, path_length.h), and a
// smooth-shaded mesh (shading normals in density estimation, photon_map.h).
// Region means are averaged over independent seeds (their spread includes the
// noise frozen into each photon map) and compared by Welch t-tests,
// Šidák-corrected, plus a stated density-estimation bias allowance.
#include <gtest/gtest.h>
#include <fstream>
#include <iostream>
#include "tests/support/consistent_helpers.h"

namespace lb::test {
namespace {

constexpr double Alpha = 1e-3;

// A GGX conductor (alpha 0.2) in a uniform environment, nothing else: every
// path is camera → sphere → environment, so neither photon map contributes
// and density estimation adds no bias: the bound is purely statistical.
// Before the fix the gather rays that escaped were dropped and photon
// mapping gave 0.03 where the path tracer gives 0.93. SPPM estimates this
// direct light by NEE alone (no MIS partner to lose).
TEST(PhotonAgreement, GlossySphereInAnEnvironment) {
  std::string scene = "camera: {position: [0, 0, 3], look_at: [0, 0, 0], fov: 30}\n"
                      "film: {width: 16, height: 16}\n"
                      "materials: {m: {type: conductor, roughness: 0.2}}\n"
                      "shapes: [{type: sphere, material: m, center: [0, 0, 0], radius: 0.8}]\n"
                      "lights: [{type: environment, radiance: 1}]\n";
  SceneFile sf = loadSceneFromString(scene, "glossy-environment.yaml");
  std::vector<bool> all(16 * 16, true);
  SeedMeans pt = maskedSeedMeans(sf, {"path", "{}", 64, 1}, 8, 2, all);
  for (auto [name, params, spp] : {std::tuple{"photon", "{global_photons: 2000, caustic_photons: 2000, final_gather: 4}", 16},
                                   std::tuple{"sppm", "{photons_per_pass: 1000}", 64}}) {
    SeedMeans m = maskedSeedMeans(sf, {name, params, uint64_t(spp), 100}, 8, 2, all);
    EXPECT_EQ(m.nonFinite, 0u);
    std::string failures = compareSeedMeans(m, pt, Alpha, 2 * 12);
    EXPECT_TRUE(failures.empty()) << name << ":" << failures;
    std::cout << name << ": glossy sphere, largest deviation from the path tracer " << 100 * deviations(m, pt).worst << " %\n";
  }
}

// The Cornell box with a mirror and a glass sphere at max_depth 4 (emission,
// direct light, two bounces; the glass caustic L S S D E is 4 segments). Each
// of photon mapping and SPPM runs at a fixed gather radius r and at r/2.
// Stated bias allowance: 15 % × r (r in world units; the box is 2 wide) of
// each region's mean. The boundary and proximity biases near edges, corners
// and the caustic are first order in r; measured at r = 0.4, 0.2, 0.1: SPPM
// −5.4 %, −2.4 %, −1.0 % and photon mapping −1.9 %, −1.3 %, −0.5 % on the top
// regions (largest region deviations 5.5 %, 3.3 %, 2.1 % for SPPM). The
// allowance halves with r, so the check at r/2 is twice as strict, and the
// summed deviation at r/2 must not exceed that at r beyond the noise.
// Bounding photon paths and camera chains separately (the old rule) adds
// paths of up to 9 segments: +25 % and more on the walls.
void cornellAtEqualDepth(const std::string& integrator, const std::string& params, const std::string& radiusKey,
                         uint64_t spp, uint64_t seed) {
  SceneFile sf = loadShippedScene("cornell-box-spheres", 16, 16);
  std::vector<bool> mask = noEmitterSeen(*sf.scene);
  const int Seeds = 8;
  SeedMeans pt = maskedSeedMeans(sf, {"path", "{max_depth: 4}", 512, 1}, Seeds, 2, mask);
  Deviations measured[2];
  double noise = 0;
  const float radii[2] = {0.2f, 0.1f};
  for (int i = 0; i < 2; ++i) {
    std::string p = "{max_depth: 4, " + params + ", " + radiusKey + ": " + std::to_string(radii[i]) + "}";
    SeedMeans m = maskedSeedMeans(sf, {integrator, p, spp, seed}, Seeds, 2, mask);
    EXPECT_EQ(m.nonFinite, 0u);
    std::string failures = compareSeedMeans(m, pt, Alpha, 2 * 12, 0.15 * radii[i]);
    EXPECT_TRUE(failures.empty()) << integrator << " at r = " << radii[i] << ":" << failures;
    measured[i] = deviations(m, pt);
    for (size_t j = 0; j < m.regions.mean.size(); ++j) noise += m.regions.varianceOfMean[j] + pt.regions.varianceOfMean[j];
  }
  std::cout << integrator << ": Cornell box with spheres, max_depth 4: largest deviation " << 100 * measured[0].worst
            << " % at r = 0.2, " << 100 * measured[1].worst << " % at r = 0.1\n";
  double z = normalCritical(Alpha);
  EXPECT_LE(measured[1].sum, measured[0].sum + z * std::sqrt(noise)) << "bias must not grow as r shrinks";
}

TEST(PhotonAgreement, PhotonMappingOnTheCornellBoxWithSpheresAtEqualMaxDepth) {
  // k above the photons in the disc: the disc is the whole max_radius.
  cornellAtEqualDepth("photon", "global_photons: 5000, caustic_photons: 5000, final_gather: 2, k: 100", "max_radius", 16, 200);
}

TEST(PhotonAgreement, SppmOnTheCornellBoxWithSpheresAtEqualMaxDepth) {
  // alpha 0.99: the radius stays within 2 % of r over the 16 passes.
  cornellAtEqualDepth("sppm", "photons_per_pass: 5000, alpha: 0.99", "initial_radius", 16, 300);
}

// A smooth-shaded tent (two 45° roof planes meeting at a ridge; OpenMesh
// averages the face normals, so the shading normal turns from the face
// normal at the eaves to vertical at the ridge) under a white ceiling lit by
// a small upward-facing light: all light on the tent arrives from above
// after a bounce off the ceiling, where |ω·n_s| > |ω·n_g| (up to √2), so a
// density estimate without the factor |ω·n_s|/|ω·n_g| (derivation in
// photon_map.h) is too dark on the whole roof; on a closed low-poly sphere
// the error would largely cancel in region means. Photon mapping shows the
// global map directly (final_gather 0: its density estimate is the whole
// tent); SPPM's photon term is all the tent's light. Fixed radius 0.04:
// stated allowance 15 % × r as above, 0.6 %.
TEST(PhotonAgreement, SmoothShadedMesh) {
  std::string dir = ::testing::TempDir();
  {
    std::ofstream obj(dir + "/photon-tent.obj");
    obj << "v -0.6 0.6 0\nv 0.6 0.6 0\nv -0.6 0 0.6\nv 0.6 0 0.6\nv -0.6 0 -0.6\nv 0.6 0 -0.6\n"
           "f 1 3 4\nf 1 4 2\nf 1 2 6\nf 1 6 5\n";
  }
  std::string scene = "camera: {position: [0, 1.3, 2.0], look_at: [0, 0.3, 0.2], fov: 35}\n"
                      "film: {width: 16, height: 16}\n"
                      "materials: {white: {type: diffuse, albedo: 0.8}}\n"
                      "shapes:\n"
                      "  - {type: rectangle, material: white, transform: {scale: 3, rotate_x: -90}}\n"
                      "  - {type: rectangle, material: white, transform: {scale: 3, rotate_x: 90, translate: [0, 2, 0]}}\n"
                      "  - {type: mesh, file: photon-tent.obj, smooth_normals: true, material: white}\n"
                      "  - {type: rectangle, material: none, emission: 20, transform: {scale: 0.2, rotate_x: -90, translate: [0, 1.6, -1]}}\n";
  SceneFile sf = loadSceneFromString(scene, dir + "/photon-shading-normals.yaml");
  std::vector<bool> mask = noEmitterSeen(*sf.scene);
  const int Seeds = 8;
  SeedMeans pt = maskedSeedMeans(sf, {"path", "{max_depth: 3}", 256, 1}, Seeds, 2, mask);
  for (auto [name, params, spp] :
       {std::tuple{"photon", "{max_depth: 3, global_photons: 20000, caustic_photons: 0, final_gather: 0, k: 1000, max_radius: 0.04}", 4},
        std::tuple{"sppm", "{max_depth: 3, photons_per_pass: 10000, initial_radius: 0.04, alpha: 0.99}", 16}}) {
    SeedMeans m = maskedSeedMeans(sf, {name, params, uint64_t(spp), 400}, Seeds, 2, mask);
    EXPECT_EQ(m.nonFinite, 0u);
    std::string failures = compareSeedMeans(m, pt, Alpha, 2 * 12, 0.15 * 0.04);
    EXPECT_TRUE(failures.empty()) << name << ":" << failures;
    std::cout << name << ": smooth-shaded mesh, largest deviation from the path tracer " << 100 * deviations(m, pt).worst << " %\n";
  }
}

}  // namespace
}  // namespace lb::test
