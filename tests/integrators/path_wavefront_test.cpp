// The wavefront engine (integrators/path/wavefront.h) is the single-ray path
// tracer's estimator traced in streams: region z-tests against the single-ray
// engine (independent seeds, bounds from the films' variance) on the Cornell
// box, Veach's MIS scene and the glass-sphere caustic, for the default
// settings and the variants it supports; with the same seed the two give the
// same numbers, pixel for pixel, wherever Embree's stream and single-ray
// traversals return the same hits; and it is deterministic across thread counts.
#include <gtest/gtest.h>
#include <cstdio>
#include <cstring>
#include "core/error.h"
#include "tests/support/render_helpers.h"

namespace lb::test {
namespace {

constexpr double Alpha = 1e-3;

const std::vector<std::string> Settings = {
    "{}",
    "{mis: one_sample}",
    "{shadow_rays: 3, emission_selection: 0.5, light_selection: spatial}",
    "{sampling: cosine, mis: balance}",
};

std::string withEngine(const std::string& settings, const char* engine) {
  std::string inner = settings.substr(1, settings.size() - 2);
  return std::string("{engine: ") + engine + (inner.empty() ? "" : ", " + inner) + "}";
}

void expectEnginesAgree(const SceneFile& sf, uint64_t spp, int regions) {
  for (const auto& s : Settings) {
    auto single = renderScene(sf, {"path", withEngine(s, "single_ray"), spp, 1});
    auto wave = renderScene(sf, {"path", withEngine(s, "wavefront"), spp, 2});
    EXPECT_EQ(wave->nonFiniteCount(), 0u) << s;
    EXPECT_EQ(compareRegions(regionMeans(*wave, regions, regions), regionMeans(*single, regions, regions),
                             Alpha / double(Settings.size())),
              "")
        << s;
  }
}

TEST(PathWavefront, AgreesWithSingleRayOnCornellBox) {
  expectEnginesAgree(loadShippedScene("cornell-box", 24, 24), 1024, 3);
}
TEST(PathWavefront, AgreesWithSingleRayOnVeachMisScene) {
  expectEnginesAgree(loadShippedScene("veach-mis", 32, 20), 1024, 4);
}
TEST(PathWavefront, AgreesWithSingleRayOnGlassSphereCaustic) {
  expectEnginesAgree(loadShippedScene("caustic-glass-sphere", 24, 24), 1024, 3);
}

// Same seed: the same random numbers and the same order of additions, so a
// pixel differs only if a stream traversal found another hit than rtcIntersect1
// (measured: none on this machine). At most 1 % of the pixels may differ.
TEST(PathWavefront, SameSeedGivesTheSingleRayImage) {
  for (std::string scene : {"cornell-box-spheres", "veach-mis", "caustic-glass-sphere"}) {
    SceneFile sf = loadShippedScene(scene, 48, 32);
    for (const auto& s : Settings) {
      Image a = renderScene(sf, {"path", withEngine(s, "single_ray"), 8, 5})->image();
      Image b = renderScene(sf, {"path", withEngine(s, "wavefront"), 8, 5})->image();
      ASSERT_EQ(a.pixels.size(), b.pixels.size());
      size_t differ = 0;
      for (size_t i = 0; i < a.pixels.size(); ++i) differ += std::memcmp(&a.pixels[i], &b.pixels[i], sizeof(Color)) != 0;
      std::printf("%s %s: %zu of %zu pixels differ\n", scene.c_str(), s.c_str(), differ, a.pixels.size());
      EXPECT_LE(differ, a.pixels.size() / 100) << scene << " " << s << ": " << differ << " pixels differ";
    }
  }
}

TEST(PathWavefront, SameSeedIsBitIdenticalWithOneAndTwoThreads) {
  for (std::string sampler : {"independent", "sobol"}) {
    // 160 × 100: more than one 64×64 batch, and partial batches at the edges.
    SceneFile s = loadShippedScene("cornell-box-spheres", 160, 100, "sampler: {type: " + sampler + "}");
    Image one = renderScene(s, {"path", "{engine: wavefront}", 4, 42, 1})->image();
    Image two = renderScene(s, {"path", "{engine: wavefront}", 4, 42, 2})->image();
    ASSERT_EQ(one.pixels.size(), two.pixels.size());
    EXPECT_EQ(std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(Color)), 0) << sampler;
  }
}

TEST(PathWavefront, RefusesBranchingPaths) {
  EXPECT_THROW(
      renderScene(loadShippedScene("cornell-box", 8, 8), {"path", "{engine: wavefront, first_bounce_samples: 2}", 1, 1}),
      ConfigError);
}

TEST(PathWavefront, MaxDepthZeroRendersBlack) {
  Image img = renderScene(loadShippedScene("cornell-box", 8, 8), {"path", "{engine: wavefront, max_depth: 0}", 2, 1})->image();
  for (const Color& c : img.pixels) EXPECT_TRUE(isBlack(c));
}

}  // namespace
}  // namespace lb::test
