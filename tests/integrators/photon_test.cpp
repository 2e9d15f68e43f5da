// Photon mapping (testing.md §5): FLANN lookups against brute force, the
// density estimate against closed-form irradiance, and the integrator
// against unbiased ones within its (stated) bias.
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <iostream>
#include "core/rng.h"
#include "integrators/photon/photon_integrator.h"
#include "tests/support/consistent_helpers.h"

namespace lb::test {
namespace {

constexpr double Alpha = 0.01;

TEST(PhotonMap, FlannSearchesMatchBruteForce) {
  Pcg32 rng(3, 3);
  std::vector<Vec3> points(20000);
  for (auto& p : points) p = Vec3(rng.next1D(), rng.next1D(), rng.next1D() * 0.2f);
  PointIndex index(points);
  std::vector<std::pair<size_t, float>> found;
  for (int q = 0; q < 300; ++q) {
    Vec3 c(rng.next1D(), rng.next1D(), rng.next1D() * 0.2f);
    std::vector<std::pair<float, size_t>> all;
    for (size_t i = 0; i < points.size(); ++i) all.push_back({glm::dot(points[i] - c, points[i] - c), i});
    std::sort(all.begin(), all.end());
    // k nearest (within an unbounded radius), nearest first.
    index.knn(c, 12, Infinity, found);
    ASSERT_EQ(found.size(), 12u);
    for (size_t i = 0; i < 12; ++i) ASSERT_EQ(found[i].first, all[i].second) << "query " << q << " rank " << i;
    // k nearest within a radius (the photon map's lookup): the nearest
    // min(k, points in the disc), nearest first; k = every point (k: 0).
    float r = 0.03f;
    size_t inDisc = size_t(std::count_if(all.begin(), all.end(), [&](auto& a) { return a.first < r * r; }));
    for (size_t k : {size_t(5), points.size()}) {
      index.knn(c, k, r, found);
      ASSERT_EQ(found.size(), std::min(k, inDisc)) << "query " << q << ", k = " << k;
      for (size_t i = 0; i < found.size(); ++i) {
        ASSERT_EQ(found[i].first, all[i].second) << "query " << q << " rank " << i << ", k = " << k;
        ASSERT_FLOAT_EQ(found[i].second, all[i].first);
      }
    }
    // Radius search (FLANN takes r²; the wrapper takes r): the same set.
    index.radius(c, r, found);
    std::vector<size_t> got, want;
    for (auto& f : found) got.push_back(f.first);
    for (auto& a : all)
      if (a.first <= r * r) want.push_back(a.second);
    std::sort(got.begin(), got.end());
    std::sort(want.begin(), want.end());
    ASSERT_EQ(got, want) << "query " << q;
  }
}

TEST(PhotonMap, IrradianceUnderAPointLightMatchesTheAnalyticValue) {
  // A point light of intensity I at height h over a large plane. Photons
  // counted within a fixed radius r of the point below the light estimate
  // the disc's mean irradiance, exactly 2I(1 − h/√(h²+r²))/r² (the disc's
  // solid angle from the light times I, over its area); the estimate is a
  // sum of n equal-power photons, so its variance is E·Φ/(πr²) (Poisson).
  // Against the point value E(0) = I/h² the estimate is biased by
  // |mean − E(0)|, which grows with r; we take r ∝ N^(-1/4) so the total
  // bound z·σ + bias shrinks as the photon count N grows.
  const float I = 10, h = 1;
  std::string scene = "camera: {position: [0, 3, 3], look_at: [0, 0, 0]}\n"
                      "film: {width: 8, height: 8}\n"
                      "materials: {m: {type: diffuse, albedo: 1}}\n"
                      "shapes: [{type: rectangle, material: m, transform: {scale: 100, rotate_x: -90}}]\n"
                      "lights: [{type: point, position: [0, 1, 0], intensity: 10}]\n";
  SceneFile sf = loadSceneFromString(scene, "photon-plane.yaml");
  double previousBound = INFINITY;
  for (size_t paths : {size_t(100000), size_t(1600000)}) {
    // Photons at their first hit only: that is irradiance from the light.
    PhotonMap map = buildPhotonMap(*sf.scene, 7, paths, 1, false);
    float r = 0.1f * std::pow(float(paths) / 1e5f, -0.25f);
    std::vector<std::pair<size_t, float>> found;
    PointIndex index([&] {
      std::vector<Vec3> p;
      for (const auto& ph : map.photons()) p.push_back(ph.p);
      return p;
    }());
    index.radius(Vec3(0.f), r, found);
    double flux = 0;
    for (auto& f : found) flux += map.photons()[f.first].power.r;
    double estimate = flux / (Pi * r * r);
    double discMean = 2 * I * (1 - h / std::sqrt(h * h + r * r)) / (r * r);
    double photonPower = double(map.photons()[0].power.r);
    double sigma = std::sqrt(discMean * photonPower / (Pi * r * r));
    double z = normalCritical(Alpha / 4);
    EXPECT_LE(std::abs(estimate - discMean), z * sigma) << paths << " photons, r = " << r;
    double exact = I / (h * h), bound = z * sigma + std::abs(discMean - exact);
    EXPECT_LE(std::abs(estimate - exact), bound) << paths << " photons";
    EXPECT_LT(bound, previousBound);
    previousBound = bound;

    // The integrator's estimator (PhotonMap::radiance, box filter, k above the
    // photons in the disc so the disc is the whole max radius) is this same
    // estimate: with a white f = 1 it returns Σ Φ / (π r²).
    DensityQuery q;
    q.k = found.size() + 10, q.maxRadius = r, q.filter = PhotonFilter::Box;
    std::vector<std::pair<size_t, float>> scratch;
    SurfaceInteraction below;
    below.p = Vec3(0.f), below.ng = Vec3(0, 1, 0), below.shading = Frame(below.ng);
    double viaMap = map.radiance(below, q, 1, [](const Vec3&) { return Color(1.f); }, scratch).r;
    EXPECT_NEAR(viaMap, estimate, 1e-5 * estimate);

    // The bias grows with the radius: on a disc of radius h/2 it is 15 % of E
    // (analytic), far beyond the ~1.5 % noise of its thousands of photons.
    float wide = 0.5f * h;
    index.radius(Vec3(0.f), wide, found);
    double wideFlux = 0;
    for (auto& f : found) wideFlux += map.photons()[f.first].power.r;
    double wideEstimate = wideFlux / (Pi * wide * wide);
    double wideMean = 2 * I * (1 - h / std::sqrt(h * h + wide * wide)) / (wide * wide);
    double wideSigma = std::sqrt(wideMean * photonPower / (Pi * wide * wide));
    EXPECT_GT(std::abs(wideMean - exact), std::abs(discMean - exact));  // analytic bias grows with r
    EXPECT_GT(exact - wideEstimate, z * wideSigma) << "the wide disc's bias must be measurable";
  }
}

// Photon mapping with final gathering on the diffuse Cornell box against the
// path tracer, region means over 16 seeds each (the spread includes the noise
// frozen into each photon map). The bias: the global map's k-nearest density
// estimate (k = 30, max_radius 1 so that k sets every radius) blurs light
// over r_k and darkens near edges and corners, where part of the disc lies
// off the surface (boundary bias); both are first order in r_k ∝ N^(-1/2)
// for N photon paths. Final gathering averages that over the room, so the
// image's bias is a fraction of it. Stated allowance c × p with
// p = sqrt(1e5 / N) (p = 1 at 10^5 photon paths), c = 0.011, measured by
// the sweep below (DISABLED_DiffuseCornellBoxBiasSweep: 16×16, 2×2 regions,
// 8 seeds, 16 spp, final_gather 8; path tracer 8 × 1024 spp) at N = 3125,
// 12500, 50000, 200000 (p = 5.66, 2.83, 1.41, 0.71): largest region
// deviation −4.24, −2.84, −1.40, −1.56 % (all regions negative at the first
// two; noise sd 0.9–1.2 %), summed 0.0319, 0.0145, 0.0069, 0.0060 (noise sd
// 0.0024–0.0013); |d| / (mean × p) = 0.0075, 0.0100, 0.0099 where resolved
// (0.022 at p = 0.71, where c × p = 0.7 % is below the noise sd); the same
// at 8 seeds and N = 3125, 12500 with other seeds: −4.44 % and −3.05 %
// (ratio 0.0108). This test's own run (16 seeds): p = 5.66: −4.77 %, summed
// 0.0326 ± 0.0015; p = 2.83: −2.78 %, summed 0.0150 ± 0.0012.
// Broken on purpose once: the photon means × 0.95 fail the allowance at
// p = 2.83 (region 0 green 0.0640 vs 0.0682, gap 0.0042 > 0.0041, 8 seeds);
// × 1.05 cancels the −3 to −5 % bias within the allowance but fails the
// shrink (summed 0.0091 at p = 5.66 → 0.0275 at 2.83, noise 0.0065); the
// smaller-N level × 0.97 (a bias that does not shrink) fails it too
// (0.0305 → 0.0387, noise 0.0097).
// The test runs N = 3125 and 12500 (r_k halves): every region within the
// seeds' t-bound plus c × p, and the summed deviation at 12500 smaller than
// at 3125 beyond the noise. (Replaces a chosen 4 % at 8e5 photons, and a
// check that the bias "must not grow".)
constexpr double PhotonCornellCoefficient = 0.011;

std::vector<BiasLevel> diffuseCornellLevels(const SceneFile& sf, const std::vector<bool>& mask,
                                            const std::vector<size_t>& photonPaths, int seeds) {
  std::vector<BiasLevel> levels;
  uint64_t seed = 1000;
  for (size_t n : photonPaths) {
    std::string params = "{global_photons: " + std::to_string(n) + ", caustic_photons: 0, final_gather: 8, max_radius: 1}";
    levels.push_back({std::sqrt(1e5 / double(n)), maskedSeedMeans(sf, {"photon", params, 16, seed}, seeds, 2, mask)});
    seed += 100;
  }
  return levels;
}

TEST(PhotonMapper, AgreesWithPathTracingOnTheDiffuseCornellBox) {
  SceneFile sf = loadShippedScene("cornell-box", 16, 16);
  std::vector<bool> mask = noEmitterSeen(*sf.scene);
  const int Seeds = 16;
  SeedMeans pt = maskedSeedMeans(sf, {"path", "{}", 256, 41}, Seeds, 2, mask);
  std::vector<BiasLevel> levels = diffuseCornellLevels(sf, mask, {3125, 12500}, Seeds);
  expectBiasWithinAndShrinking("photon, diffuse Cornell box", levels, pt, PhotonCornellCoefficient, 1e-3,
                               2 * 2 * 3 * int(levels.size()));
}

TEST(PhotonMapper, DISABLED_DiffuseCornellBoxBiasSweep) {
  SceneFile sf = loadShippedScene("cornell-box", 16, 16);
  std::vector<bool> mask = noEmitterSeen(*sf.scene);
  SeedMeans pt = maskedSeedMeans(sf, {"path", "{}", 1024, 41}, 8, 2, mask);
  printBiasSweep("photon, diffuse Cornell box", diffuseCornellLevels(sf, mask, {3125, 12500, 50000, 200000}, 8), pt);
}

}  // namespace
}  // namespace lb::test
