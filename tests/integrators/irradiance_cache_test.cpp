// The irradiance-cache integrator: convergence in a on the Cornell box,
// thread-count independence, and its settings.
#include <gtest/gtest.h>
#include <cstring>
#include <iostream>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include "core/scene_loader.h"
#include "integrators/render_loop.h"
#include <yaml-cpp/yaml.h>
#include "integrators/irradiance_cache/irradiance_cache.h"
#include "integrators/irradiance_cache/irradiance_cache_integrator.h"
#include "tests/support/consistent_helpers.h"
#include "tests/support/statistics.h"

namespace lb {
namespace {
using namespace lb::test;
IrradianceCacheSettings icSettings(const std::string& yaml) {
  Params p(YAML::Load(yaml), "<test>", "integrator");
  return IrradianceCacheSettings::read(p);
}

// A cache built by rendering, then queried at the diffuse surfaces seen
// through the centres of a coarse grid of pixels.
struct SurfacePoint {
  SurfaceInteraction si;
  Vec3 n;  // shading normal turned towards the camera
};
std::vector<SurfacePoint> diffuseSurfacePoints(const Scene& scene, int step) {
  std::vector<SurfacePoint> points;
  const Camera& cam = scene.camera;
  for (int y = step / 2; y < cam.height(); y += step)
    for (int x = step / 2; x < cam.width(); x += step) {
      SurfaceInteraction si;
      // Off the pixel centre, which falls on the box's seams and diagonals (as in indirect_bench.cpp).
      if (!scene.intersect(cam.generateRay(Vec2(x + 0.37f, y + 0.61f)), si) || si.emitter || !si.material) continue;
      if (si.material->flags() != (BSDFReflection | BSDFDiffuse)) continue;
      Vec3 n = glm::dot(si.wo, si.shading.n) < 0 ? -si.shading.n : si.shading.n;
      points.push_back({si, n});
    }
  return points;
}

// Reference indirect irradiance at each point: the mean of two independent
// fine records, and the variance of that mean from their difference.
struct ReferenceIrradiance {
  std::vector<Color> E, varianceOfMean;
};
ReferenceIrradiance referenceIrradiance(const SceneFile& sf, const std::vector<SurfacePoint>& points) {
  IrradianceCacheIntegrator fine(icSettings("{theta_strata: 64, phi_strata: 192, prepass_levels: 0}"));
  auto sampler = makeSampler(sf.sampler, 99);
  fine.preprocess(*sf.scene, *sampler);
  ReferenceIrradiance ref;
  std::vector<std::pair<Color, Color>> pairs(points.size());
  tbb::parallel_for(size_t(0), points.size(), [&](size_t i) {
    uint64_t rays = 0;
    pairs[i].first = fine.computeRecordAt(points[i].si, 2 * i, 31, rays).E;
    pairs[i].second = fine.computeRecordAt(points[i].si, 2 * i + 1, 31, rays).E;
  });
  for (auto& [a, b] : pairs) {
    ref.E.push_back(0.5f * (a + b));
    ref.varianceOfMean.push_back(0.25f * (a - b) * (a - b));  // (a−b)²/2 estimates σ²; the mean of two has σ²/2
  }
  return ref;
}

struct CacheError {
  double squaredError = 0;  // mean over points and channels, reference noise removed
  size_t records = 0, missed = 0;
};
CacheError cacheError(const SceneFile& sf, const std::string& params, uint64_t seed,
                      const std::vector<SurfacePoint>& points, const ReferenceIrradiance& ref) {
  IrradianceCacheIntegrator ic(icSettings(params));
  Film film(sf.scene->camera.width(), sf.scene->camera.height());
  RenderOptions options;
  options.seed = seed;
  options.budget.spp = 4;
  renderLoop(*sf.scene, ic, film, sf.sampler, options);
  CacheError e;
  e.records = ic.cache().size();
  LocalRecords none;
  size_t used = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    Color E;
    if (!ic.cache().interpolate(points[i].si.p, points[i].n, none, E)) {
      ++e.missed;
      continue;
    }
    for (int c = 0; c < 3; ++c) e.squaredError += sqr(E[c] - ref.E[i][c]) - ref.varianceOfMean[i][c];
    ++used;
  }
  e.squaredError /= double(3 * std::max<size_t>(used, 1));
  return e;
}

// Against fine path-traced records (64×192 strata, two per point), the
// cache's irradiance error falls as a falls (interpolation blurs less) while
// the record count grows. Three seeds per a; a step counts as "error shrinks"
// only if every error at the smaller a is below every error at the larger
// one: a Mann–Whitney test with U = 0, which has probability 1/20 per step if
// a made no difference. Records use 32×96 strata so that their own noise stays
// below the interpolation error being measured.
TEST(IrradianceCacheCornell, ErrorShrinksAndRecordsGrowAsADecreases) {
  SceneFile sf = loadShippedScene("cornell-box", 32, 32);
  std::vector<SurfacePoint> points = diffuseSurfacePoints(*sf.scene, 2);
  ReferenceIrradiance ref = referenceIrradiance(sf, points);
  const std::vector<float> thresholds = {0.8f, 0.4f, 0.2f};
  std::vector<std::vector<CacheError>> runs(thresholds.size());
  for (size_t i = 0; i < thresholds.size(); ++i)
    for (uint64_t seed = 1; seed <= 3; ++seed) {
      runs[i].push_back(cacheError(sf, "{spacing: world, min_spacing: 0.01, max_spacing: 2, theta_strata: 32, phi_strata: 96, a: " +
                                           std::to_string(thresholds[i]) + "}", seed, points, ref));
      // Points between the rendered samples may find no record (more as a falls,
      // since records reach a·R); the error must still cover two thirds of them.
      EXPECT_LT(runs[i].back().missed, points.size() / 3) << "a " << thresholds[i];
    }
  for (size_t i = 1; i < thresholds.size(); ++i) {
    double worstSmaller = 0, bestLarger = Infinity;
    for (int s = 0; s < 3; ++s) {
      worstSmaller = std::max(worstSmaller, runs[i][s].squaredError);
      bestLarger = std::min(bestLarger, runs[i - 1][s].squaredError);
      EXPECT_GT(runs[i][s].records, runs[i - 1][s].records) << "records must grow as a falls (seed " << s + 1 << ")";
    }
    EXPECT_LT(worstSmaller, bestLarger) << "squared error at a = " << thresholds[i] << " vs a = " << thresholds[i - 1];
  }
}

// Records created during a pass join the cache after it, in tile order, so
// the cache and the image cannot depend on the thread count.
TEST(IrradianceCacheDeterminism, SameImageAndRecordsWithOneAndTwoThreads) {
  SceneFile sf = loadShippedScene("cornell-box", 48, 48);
  auto render = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    auto ic = std::make_unique<IrradianceCacheIntegrator>(icSettings("{theta_strata: 8, phi_strata: 24}"));
    auto film = std::make_unique<Film>(48, 48);
    RenderOptions options;
    options.seed = 5;
    options.budget.spp = 3;
    renderLoop(*sf.scene, *ic, *film, sf.sampler, options);
    return std::pair{std::move(ic), std::move(film)};
  };
  auto [ic1, film1] = render(1);
  auto [ic2, film2] = render(2);
  ASSERT_EQ(ic1->cache().size(), ic2->cache().size());
  ASSERT_GT(ic1->cache().size(), 0u);
  for (size_t i = 0; i < ic1->cache().size(); ++i) {
    const IrradianceRecord &a = ic1->cache().records()[i], &b = ic2->cache().records()[i];
    ASSERT_TRUE(a.p == b.p && a.n == b.n && a.E == b.E && a.R == b.R) << "record " << i;
    for (int c = 0; c < 3; ++c)
      ASSERT_TRUE(a.translationalGradient[c] == b.translationalGradient[c] && a.rotationalGradient[c] == b.rotationalGradient[c])
          << "record " << i;
  }
  Image i1 = film1->image(), i2 = film2->image();
  EXPECT_EQ(0, std::memcmp(i1.pixels.data(), i2.pixels.data(), i1.pixels.size() * sizeof(Color)));
}

TEST(IrradianceCacheSettings, RejectsNonPhysicalAndMisplacedKeys) {
  auto read = [](const std::string& yaml) { return icSettings(yaml); };
  EXPECT_THROW(read("{a: 0}"), ConfigError);
  EXPECT_THROW(read("{min_spacing: 5, max_spacing: 1}"), ConfigError);
  EXPECT_THROW(read("{theta_strata: 0}"), ConfigError);
  EXPECT_THROW(read("{k: 10}"), ConfigError);  // a photon key without base: photon
  EXPECT_NO_THROW(read("{base: photon, k: 10, global_photons: 1000}"));
}

// The cache against the path tracer on the diffuse Cornell box, region
// means over 16 seeds each (the seeds' spread includes each record's noise,
// frozen into a blotch). The bias is interpolation's: records reach a·R
// (R: the harmonic mean distance of its hemisphere rays) and blur irradiance
// over that reach, most where it changes fastest (corners, contact shadows);
// Ward's threshold a bounds the relative interpolation error to first order
// in a. Stated allowance c × a of each region's mean, c = 0.05, measured by
// the sweep below (DISABLED_DiffuseBoxBiasSweep: 16×16, 2×2 regions, 8
// seeds, 16×48 strata, 4 spp; path tracer 8 × 1024 spp): at a = 0.8, 0.4,
// 0.2, 0.1 the largest region deviation was 3.75, 1.92, 0.75, 1.90 % (noise
// sd 1.4–2.0 %), the summed deviation 0.0149, 0.0068, 0.0043, 0.0062 (noise
// sd 0.0025–0.0027): |d| / (mean × a) = 0.047 and 0.048 where the bias is
// resolved (a = 0.8, 0.4), below a = 0.2 flat within the noise. In this
// test (16 seeds): a = 0.8: largest 3.97 %, summed 0.0166 ± 0.0020; a = 0.2:
// largest 2.12 % (noise sd 1.1 %), summed 0.0051 ± 0.0019. Broken on
// purpose once: the cache's means × 1.05 fail at both a (e.g. a = 0.8,
// region 0 red 0.196 vs 0.182, gap 0.0144 > 0.0122); the a = 0.2 level
// × 0.97 (a bias that does not shrink) fails the shrink (summed 0.0166 →
// 0.0244, noise 0.0090).
// Not on the Cornell box with spheres (consistent_scenes_test.cpp): records
// there see the light through the glass sphere by chance, and that frozen
// noise gives region means a seed-to-seed sd of several percent, too wide
// to resolve a bias shrinking with a.
// The test runs a = 0.8 and 0.2: every region within the seeds' t-bound plus
// c × a, and the summed deviation at 0.2 smaller than at 0.8 beyond the noise.
constexpr double CacheCoefficient = 0.05;

std::vector<BiasLevel> cacheLevels(const SceneFile& sf, const std::vector<bool>& mask, const std::vector<double>& as,
                                   int seeds) {
  std::vector<BiasLevel> levels;
  uint64_t seed = 3000;
  for (double a : as) {
    std::string params = "{a: " + std::to_string(a) +
                         ", spacing: world, min_spacing: 0.005, theta_strata: 16, phi_strata: 48, record_image: false}";
    levels.push_back({a, maskedSeedMeans(sf, {"irradiance_cache", params, 4, seed}, seeds, 2, mask)});
    seed += 100;
  }
  return levels;
}

TEST(IrradianceCacheCornell, BiasWithinItsAllowanceAndShrinkingWithA) {
  SceneFile sf = loadShippedScene("cornell-box", 16, 16);
  std::vector<bool> mask = noEmitterSeen(*sf.scene);
  // 32 seeds: with 16, the shrink from a = 0.8 to 0.2 (about 0.010 summed)
  // was within the 3.3σ margin (about 0.009) often enough that 2 of 7 seed
  // bases failed; 32 seeds narrow the margin by √2.
  const int Seeds = 32;
  SeedMeans pt = maskedSeedMeans(sf, {"path", "{}", 128, 3}, Seeds, 2, mask);
  std::vector<BiasLevel> levels = cacheLevels(sf, mask, {0.8, 0.2}, Seeds);
  expectBiasWithinAndShrinking("irradiance cache, diffuse Cornell box", levels, pt, CacheCoefficient, 1e-3,
                               2 * 2 * 3 * int(levels.size()));
}

TEST(IrradianceCacheCornell, DISABLED_DiffuseBoxBiasSweep) {
  SceneFile sf = loadShippedScene("cornell-box", 16, 16);
  std::vector<bool> mask = noEmitterSeen(*sf.scene);
  SeedMeans pt = maskedSeedMeans(sf, {"path", "{}", 1024, 3}, 8, 2, mask);
  printBiasSweep("irradiance cache, diffuse Cornell box", cacheLevels(sf, mask, {0.8, 0.4, 0.2, 0.1}, 8), pt);
}

// On the Cornell box with a mirror and a glass sphere (specular chains to
// diffuse surfaces, caustics inside records) the cache is held to BDPT per
// region over seeds, with an allowance from a sweep over a, in
// consistent_scenes_test.cpp (PathCacheOnTheCornellBoxWithSpheres); it
// replaced a chosen 5 % allowance here.

}  // namespace
}  // namespace lb
