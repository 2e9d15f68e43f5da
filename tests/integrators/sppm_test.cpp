// SPPM (testing.md §5): the radius/flux update follows Hachisuka & Jensen's
// formula; the estimate is consistent (error against a BDPT reference falls
// with time); deterministic for a seed; and the photon mapper's caustic agrees
// with BDPT where the caustic is brightest.
#include <gtest/gtest.h>
#include <cstring>
#include "integrators/photon/photon_integrator.h"
#include "integrators/render_loop.h"
#include "integrators/sppm/sppm.h"
#include "tests/support/render_helpers.h"

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

TEST(PhotonMapper, CausticUnderTheGlassSphereAgreesWithBdpt) {
  // The brightest 8×8 block of BDPT's image of the caustic scene is the
  // caustic; the photon map's mean there must agree within BDPT's z-bound plus
  // the stated density-estimation bias: 15% (the disc blurs the caustic's
  // sharp edge into its dark surround — the proximity bias).
  SceneFile sf = loadShippedScene("caustic-glass-sphere", 64, 48);
  auto bd = renderScene(sf, {"bdpt", "{}", 1024, 61});
  Image b = bd->image(), var = bd->varianceOfMean();
  int bx = 0, by = 0;
  double best = -1;
  for (int y = 0; y + 8 <= 48; y += 2)
    for (int x = 0; x + 8 <= 64; x += 2) {
      double s = 0;
      for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i) s += luminance(b.at(x + i, y + j));
      if (s > best) best = s, bx = x, by = y;
    }
  auto pm = renderScene(sf, {"photon", "{caustic_photons: 1000000, global_photons: 100000}", 16, 62});
  Image p = pm->image();
  double mb = 0, mp = 0, vb = 0;
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) {
      mb += luminance(b.at(bx + i, by + j)) / 64, mp += luminance(p.at(bx + i, by + j)) / 64;
      Color v = var.at(bx + i, by + j);
      vb += (v.r + v.g + v.b) / 3 / (64.0 * 64.0);  // channels are equal here (white light, grey floor)
    }
  EXPECT_LE(std::abs(mp - mb), normalCritical(Alpha) * std::sqrt(vb) + 0.15 * mb)
      << "caustic block at (" << bx << "," << by << "): photon " << mp << " vs BDPT " << mb;
}

}  // namespace
}  // namespace lb::test
