// The path tracer's classic variants (one-sample MIS, emit vs reflect,
// splitting, light selection, variance-aware MIS with its learned factors,
// learned roulette and splitting)
// estimate the same image as the default path tracer: region z-tests (testing.md §3) with bounds from the films' measured
// variance, on the Cornell box, Veach's MIS scene (four lights) and the
// glass-sphere caustic. The independent sampler keeps each pixel's samples
// independent, which the films' variance estimate assumes.
#include <gtest/gtest.h>
#include <cstring>
#include "core/spatial_light_sampler.h"
#include "integrators/path_estimator/path_estimator.h"
#include "tests/support/render_helpers.h"
#include "tests/support/statistics.h"

namespace lb::test {
namespace {

constexpr double Alpha = 1e-3;

// Variants with next-event estimation, for every scene.
const std::vector<std::string> Variants = {
    "{mis: one_sample}",
    "{mis: one_sample, light_selection_probability: 0.2}",
    "{emission_selection: 0.9}",
    "{shadow_rays: 4}",
    "{first_bounce_samples: 4, mis: balance}",
    "{shadow_rays: 2, first_bounce_samples: 3, emission_selection: 0.3}",
    "{light_selection: uniform}",
    "{light_selection: spatial}",
    "{light_selection: spatial, mis: one_sample}",
    "{mis: variance_aware}",
    "{mis: variance_aware, pilot_passes: 4, factor_block: 2, shadow_rays: 2}",
    "{rrs: adrrs}",
    "{rrs: ears}",
    "{rrs: ears, rrs_warmup: 1, rrs_cells: 2, rrs_min_samples: 1, shadow_rays: 2}",
};
// Variants whose directions ignore the glossy lobes, or that find lights only
// by hitting them: on Veach's plates and the caustic's small light their
// rare large samples make the films' variance estimate unreliable, so they
// are tested where that estimate holds (the Cornell box's large light).
const std::vector<std::string> CornellOnly = {
    "{mis: one_sample, light_selection_probability: 0.2, sampling: cosine}",
    "{emission_selection: 0.5, nee: false}",
};

void expectVariantsAgree(const SceneFile& sf, uint64_t spp, int regions, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> variants = Variants;
  variants.insert(variants.end(), extra.begin(), extra.end());
  auto reference = regionMeans(*renderScene(sf, {"path", "{}", 2 * spp, 100}), regions, regions);
  uint64_t seed = 1;
  for (const auto& v : variants) {
    auto film = renderScene(sf, {"path", v, spp, seed++});
    EXPECT_EQ(film->nonFiniteCount(), 0u) << v;
    EXPECT_EQ(compareRegions(regionMeans(*film, regions, regions), reference, Alpha / double(variants.size())), "")
        << v;
  }
}

TEST(PathVariants, AgreeOnCornellBox) {
  expectVariantsAgree(loadShippedScene("cornell-box", 24, 24), 1024, 3, CornellOnly);
}

TEST(PathVariants, AgreeOnVeachMisScene) { expectVariantsAgree(loadShippedScene("veach-mis", 32, 20), 1024, 4); }

TEST(PathVariants, AgreeOnGlassSphereCaustic) {
  expectVariantsAgree(loadShippedScene("caustic-glass-sphere", 24, 24), 1024, 3);
}

// The furnace (a closed emitting sphere of albedo a: L = 1/(1 − a)), where
// every vertex is an emitter the path can leave again, so emit vs reflect
// chooses at every bounce, one-sample MIS at every vertex, and every sample is
// of finite variance: each variant against the exact value. Emit vs reflect
// multiplies β by a/(1 − p) at each reflection chosen with probability
// 1 − p, so its second moment is finite only if a² < 1 − p: p ≤ 0.3 for
// a = 0.8 (p = 0.9 there has infinite variance, and a z-test would be void).
TEST(PathVariants, FurnaceGivesOneOverOneMinusAlbedo) {
  const std::vector<std::string> furnaceVariants = {
      "{emission_selection: 0.3}",           "{emission_selection: 0.3, nee: false}",
      "{emission_selection: 0.2, mis: one_sample}", "{mis: one_sample, light_selection_probability: 0.7}",
      "{shadow_rays: 3, first_bounce_samples: 2}",   "{light_selection: spatial}",
      "{engine: wavefront, emission_selection: 0.3}"};
  int tests = 2 * int(furnaceVariants.size());
  for (float a : {0.5f, 0.8f}) {
    SceneFile sf = loadSceneFromString(furnaceScene(a), "furnace.yaml");
    for (const auto& v : furnaceVariants) {
      std::string params = v.substr(0, v.size() - 1) + ", max_depth: -1}";
      auto film = renderScene(sf, {"path", params, 64, 3});
      EXPECT_TRUE(meanMatches(*film, 1 / (1 - a), Alpha / tests)) << "albedo " << a << " " << v;
      EXPECT_EQ(film->nonFiniteCount(), 0u);
    }
  }
}

// Veach 1997 Eq. 9.15 with the balance heuristic over c_i p_i: the weights
// are a partition of unity, and at q = 1/2 they are the ordinary balance
// heuristic (core/sampling.h, written separately).
TEST(PathVariants, OneSampleMisWeightsSumToOne) {
  for (float q : {0.05f, 0.3f, 0.5f, 0.9f})
    for (float pl : {1e-6f, 0.1f, 1.f, 40.f})
      for (float pf : {1e-6f, 0.3f, 2.f, 100.f}) {
        OneSampleWeights w = oneSampleMisWeights(q, pl, pf);
        EXPECT_NEAR(w.light + w.bsdf, 1.f, 1e-6f);
        if (q == 0.5f) {
          EXPECT_NEAR(w.light, balanceHeuristic(pl, pf), 1e-6f);
        }
      }
  OneSampleWeights none = oneSampleMisWeights(0.5f, 0.f, 0.f);
  EXPECT_EQ(none.light + none.bsdf, 0.f);  // a direction neither strategy samples
}

// The spatial table is a distribution at every point: its sample() follows
// its pmf() (chi²), the pmfs sum to 1, and every emitting light keeps a
// positive probability everywhere (the defensive mixture).
TEST(PathVariants, SpatialLightSamplerSamplesItsOwnPmf) {
  SceneFile sf = loadShippedScene("veach-mis", 32, 20);
  const Scene& scene = *sf.scene;
  SpatialLightSampler spatial(scene, 5);
  EXPECT_GT(spatial.resolution(), 1);
  Pcg32 rng(3, 4);
  const Bounds3& b = scene.bounds();
  for (int trial = 0; trial < 6; ++trial) {
    Vec3 t(rng.next1D(), rng.next1D(), rng.next1D());
    Vec3 p = b.lo + (b.hi - b.lo) * t;
    size_t L = scene.lights().size();
    std::vector<double> observed(L, 0), expected(L, 0);
    double sum = 0;
    for (const auto& light : scene.lights()) {
      float pmf = spatial.pmf(p, light.get());
      sum += pmf;
      EXPECT_GE(pmf, SpatialLightSampler::DefensiveFraction * scene.lightSampler().pmf(light.get()) * 0.999f);
    }
    EXPECT_NEAR(sum, 1.0, 1e-5);
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
      float pmf = 0;
      const Light* l = spatial.sample(p, rng.next1D(), &pmf);
      ASSERT_NE(l, nullptr);
      EXPECT_EQ(pmf, spatial.pmf(p, l));
      observed[size_t(l->index)] += 1;
    }
    for (const auto& light : scene.lights()) expected[size_t(light->index)] = n * spatial.pmf(p, light.get());
    auto r = chi2Test(observed, expected);
    EXPECT_TRUE(r.passed(Alpha)) << r.message << " p=" << r.pValue;
  }
}

// Splitting and branching draw fixed dimensions per vertex: images stay
// bit-identical across thread counts for every sampler.
TEST(PathVariants, SameSeedIsBitIdenticalWithOneAndTwoThreads) {
  for (std::string sampler : {"independent", "stratified", "sobol", "zsobol", "halton"}) {
    SceneFile s = loadShippedScene("cornell-box-spheres", 24, 24, "sampler: {type: " + sampler + "}");
    const char* params = "{shadow_rays: 2, first_bounce_samples: 2, emission_selection: 0.5, light_selection: spatial}";
    Image one = renderScene(s, {"path", params, 4, 42, 1})->image();
    Image two = renderScene(s, {"path", params, 4, 42, 2})->image();
    ASSERT_EQ(one.pixels.size(), two.pixels.size());
    EXPECT_EQ(std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(Color)), 0) << sampler;
  }
}

TEST(PathVariants, OneSampleMisRefusesSeveralShadowRays) {
  EXPECT_THROW(renderScene(loadShippedScene("cornell-box", 8, 8), {"path", "{mis: one_sample, shadow_rays: 2}", 1, 1}),
               ConfigError);
}

// MIS compensation (core/lights/light.h) leaves directions to BSDF sampling
// under MIS; an estimator without it would lose them, so it is refused.
TEST(PathVariants, MisCompensationIsRefusedWhereBsdfSamplingCannotCoverIt) {
  SceneFile scene = loadShippedScene("cornell-box", 8, 8);
  for (const char* params : {"{mis_compensation: true, mis: none}", "{mis_compensation: true, nee: false}",
                             "{mis_compensation: true, sampling: cosine}", "{mis_compensation: true, sampling: uniform}"}) {
    try {
      renderScene(scene, {"path", params, 1, 1});
      ADD_FAILURE() << params << " was accepted";
    } catch (const ConfigError& e) {
      // The refusal's own message, not an unknown key's.
      std::string what = e.what();
      EXPECT_NE(what.find("mis_compensation"), std::string::npos) << what;
      EXPECT_NE(what.find("needs"), std::string::npos) << what;
    }
  }
}

}  // namespace
}  // namespace lb::test
