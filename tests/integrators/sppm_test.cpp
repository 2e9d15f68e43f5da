// SPPM (testing.md §5): the radius/flux update follows Hachisuka & Jensen's
// formula; the estimate is consistent (error against a BDPT reference falls
// with time); deterministic for a seed; and the photon mapper's caustic agrees
// with BDPT where the caustic is brightest, within a bias allowance that
// shrinks with the gather radius.
#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <cstring>
#include "integrators/photon/photon_integrator.h"
#include "integrators/render_loop.h"
#include "integrators/sppm/sppm.h"
#include "tests/support/consistent_helpers.h"

namespace lb::test {
namespace {

constexpr double Alpha = 0.01;

TEST(Sppm, RadiusAndFluxFollowTheUpdateFormula) {
  // N' = N + αM, R' = R·sqrt((N + αM)/(N + M)), τ' = (τ + Φ)·R'²/R² — by hand:
  SppmPixel p{0, 1.f, glm::dvec3(0)};
  p.update(10, glm::dvec3(2), 0.7f);  // N: 0 → 7, R² = 1·7/10, τ = 2·0.7
  EXPECT_NEAR(p.N, 7, 1e-6);  // α is a float: 0.7f
  EXPECT_NEAR(p.R * p.R, 0.7f, 1e-6f);
  EXPECT_NEAR(p.tau.x, 1.4, 1e-6);
  p.update(5, glm::dvec3(1), 0.7f);   // N: 7 → 10.5, R² = 0.7·10.5/12, τ = (1.4 + 1)·(10.5/12)
  EXPECT_NEAR(p.N, 10.5, 1e-6);
  EXPECT_NEAR(p.R * p.R, 0.7f * 10.5f / 12.f, 1e-6f);
  EXPECT_NEAR(p.tau.x, 2.4 * 10.5 / 12, 1e-6);
  p.update(0, glm::dvec3(0), 0.7f);   // no photons: nothing changes
  EXPECT_NEAR(p.N, 10.5, 1e-6);
}

double rmse(const Image& a, const Image& b) {
  double s = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) s += double(a.pixels[i][c] - b.pixels[i][c]) * (a.pixels[i][c] - b.pixels[i][c]);
  return std::sqrt(s / (3.0 * a.pixels.size()));
}

TEST(Sppm, ErrorFallsBetweenOneAndFourTimesTheTime) {
  SceneFile sf = loadShippedScene("cornell-box-spheres", 32, 32);
  auto reference = renderScene(sf, {"bdpt", "{}", 2048, 51});
  Image ref = reference->image();
  double refNoise = std::sqrt(reference->meanVarianceOfMean());
  SppmSettings s;
  s.photonsPerPass = 20000;
  Sppm sppm(s);
  Film film(32, 32);
  RenderOptions o;
  o.seed = 52;
  double rmseAt[2];
  uint64_t passes[2] = {16, 64};
  std::vector<float> radiusAfter;
  for (int i = 0; i < 2; ++i) {
    o.budget.spp = passes[i] - (i ? passes[0] : 0);
    // Continue the same progressive render: passes 0…15, then 16…63.
    auto sampler = makeSampler(sf.sampler, o.seed);
    PassStats stats;
    for (uint64_t pass = i ? passes[0] : 0; pass < passes[i]; ++pass) sppm.renderPass(*sf.scene, film, *sampler, pass, stats);
    rmseAt[i] = rmse(film.image(), ref);
  }
  // The reference's own noise is far below both errors, so it cannot decide the comparison.
  EXPECT_LT(refNoise, 0.5 * rmseAt[1]);
  EXPECT_LT(rmseAt[1], rmseAt[0]) << "16 passes: " << rmseAt[0] << ", 64 passes: " << rmseAt[1];
  // Radii only shrink.
  for (const auto& p : sppm.pixels()) EXPECT_LE(p.R, s.relativeRadius * sf.scene->bounds().radius());
}

TEST(Sppm, SameSeedIsBitIdenticalWithOneAndTwoThreads) {
  SceneFile sf = loadShippedScene("cornell-box-spheres", 24, 24);
  Image one = renderScene(sf, {"sppm", "{photons_per_pass: 10000}", 4, 42, 1})->image();
  Image two = renderScene(sf, {"sppm", "{photons_per_pass: 10000}", 4, 42, 2})->image();
  EXPECT_EQ(std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(Color)), 0);
}

TEST(Sppm, GridAndFlannLookupsFindTheSameVisiblePoints) {
  // Each photon deposits at most once per pixel, in photon order, whichever
  // structure finds the points: the images must be identical bit for bit (a
  // duplicated or missed visible point in either would show).
  SceneFile sf = loadShippedScene("cornell-box-spheres", 24, 24);
  Image grid = renderScene(sf, {"sppm", "{photons_per_pass: 20000, lookup: grid}", 6, 5})->image();
  Image flann = renderScene(sf, {"sppm", "{photons_per_pass: 20000, lookup: flann}", 6, 5})->image();
  EXPECT_EQ(std::memcmp(grid.pixels.data(), flann.pixels.data(), grid.pixels.size() * sizeof(Color)), 0);
}

// The photon mapper's caustic under the glass sphere against BDPT, on the
// 4×4 block (at 64×48) where the caustic seen directly (every pixel's primary
// hit diffuse) is brightest, chosen on an independent light-tracing image
// (choosing it on the reference's own image would bias the reference
// upwards). Both sides are means over 8 seeds: the photon side's spread
// includes the noise frozen into its caustic map. The caustic map's discs
// hold the k = 400 nearest photons, r_k ∝ N^(-1/2) for N caustic photon
// paths (≈ 0.05 in the caustic at N = 10^5; the sphere's radius is 0.5);
// max_radius 0.25 bounds the sparse global map's discs.
// Measured by the sweep below (DISABLED_CausticBiasSweep, 8 seeds, BDPT
// 8 × 256 spp) at N = 6250, 25000, 1e5, 4e5, i.e. p = sqrt(1e5 / N) = 4, 2,
// 1, 0.5: deviations −1.44, −1.22, −1.41, −0.29 % (noise sd 0.50, 0.63,
// 0.61, 0.38 %); on an 8×8 block −0.37, −0.45, −0.25, −0.17 %. So the
// proximity bias on this caustic, seen directly, is at most ~1.5 % up to
// r_k ≈ 0.2, and its shrinking is not resolvable within a test's time (the
// diffuse Cornell box test in photon_test.cpp shows it); a second run at
// p = 4 gave −0.63 %. Stated allowance c × p with c = 0.015, the largest
// |d| / (mean × p) measured (0.0141 at p = 1), run at p = 1: 1.5 % beyond
// the seeds' t-bound (measured in this test: −0.04 ± 0.40 %). Broken on
// purpose once: the photon means × 1.05 fail (0.1028 vs 0.0979, gap 0.0049
// > 0.0029). (Replaces a chosen 15 % on one render of each.)
// Caution: a block that includes pixels seeing the floor through the sphere
// (L S D S S E paths) has the photon mapper 28 % above BDPT at N ≥ 1e5: BDPT
// can sample those paths only by hitting the tiny light after the glass
// (s = 0), so its mean there is short of light with a variance that does not
// show it; hence the directly-seen block.
constexpr double CausticCoefficient = 0.015;

constexpr int Block = 4;  // pixels on a side

std::vector<bool> brightestCausticBlock(const SceneFile& sf) {
  Image sel = renderScene(sf, {"light", "{}", 32, 60})->image();
  std::vector<bool> diffuse = diffusePrimaryHits(*sf.scene);
  int w = sel.width, h = sel.height, bx = 0, by = 0;
  double best = -1;
  for (int y = 0; y + Block <= h; ++y)
    for (int x = 0; x + Block <= w; ++x) {
      double s = 0;
      bool seenDirectly = true;
      for (int j = 0; j < Block; ++j)
        for (int i = 0; i < Block; ++i)
          s += luminance(sel.at(x + i, y + j)), seenDirectly = seenDirectly && diffuse[size_t(y + j) * w + x + i];
      if (seenDirectly && s > best) best = s, bx = x, by = y;
    }
  std::printf("caustic block at (%d, %d)\n", bx, by);
  std::vector<bool> block(size_t(w) * h, false);
  for (int j = 0; j < Block; ++j)
    for (int i = 0; i < Block; ++i) block[size_t(by + j) * w + bx + i] = true;
  return block;
}

std::vector<BiasLevel> causticLevels(const SceneFile& sf, const std::vector<bool>& block,
                                     const std::vector<size_t>& causticPaths, int seeds) {
  std::vector<BiasLevel> levels;
  uint64_t seed = 2000;
  for (size_t n : causticPaths) {
    std::string params = "{caustic_photons: " + std::to_string(n) +
                         ", global_photons: 20000, final_gather: 4, k: 400, max_radius: 0.25}";
    levels.push_back({std::sqrt(1e5 / double(n)), maskedSeedMeans(sf, {"photon", params, 4, seed}, seeds, 1, block)});
    seed += 100;
  }
  return levels;
}

TEST(PhotonMapper, CausticUnderTheGlassSphereAgreesWithBdpt) {
  SceneFile sf = loadShippedScene("caustic-glass-sphere", 64, 48);
  std::vector<bool> block = brightestCausticBlock(sf);
  const int Seeds = 8;
  SeedMeans bd = maskedSeedMeans(sf, {"bdpt", "{}", 64, 61}, Seeds, 1, block);
  std::vector<BiasLevel> levels = causticLevels(sf, block, {100000}, Seeds);
  expectBiasWithinAndShrinking("photon, glass-sphere caustic block", levels, bd, CausticCoefficient, Alpha,
                               3 * int(levels.size()));
}

TEST(PhotonMapper, DISABLED_CausticBiasSweep) {
  SceneFile sf = loadShippedScene("caustic-glass-sphere", 64, 48);
  std::vector<bool> block = brightestCausticBlock(sf);
  SeedMeans bd = maskedSeedMeans(sf, {"bdpt", "{}", 256, 61}, 8, 1, block);
  printBiasSweep("photon, glass-sphere caustic block", causticLevels(sf, block, {6250, 25000, 100000, 400000}, 8), bd);
}

}  // namespace
}  // namespace lb::test
