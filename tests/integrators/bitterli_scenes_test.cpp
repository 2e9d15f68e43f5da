// Every shipped scene of Bitterli's (scenes/external/, issue 35) renders with
// path tracing and BDPT, and they agree: region means over 8 seeds of each
// at small resolution, Welch's t, Šidák-corrected at 1e-3 per scene
// (pathBdptDisagreement). The scenes' own max_depth and materials, as
// imported; the film made small. What this catches: a term lost or counted
// twice by the importer's translation or a BSDF one transport direction sees
// differently (the plastics, textures, envmap, many lights); the measured
// noise of each below says how large a difference it resolves.
//
// Relative sd of a region's mean over the 8 seeds, median / largest over
// regions and channels with signal, path then BDPT (DISABLED_ test below,
// 2026-12-06): veach-ajar 2.6 / 8.1 % and 2.5 / 4.9 %, coffee 0.8 / 2.8 %
// and 1.1 / 3.6 % (its pbrt file 0.6 / 1.7 %, 0.9 / 3.1 %), staircase 0.6 /
// 3.3 % and 0.8 / 6.4 %, living-room 0.9 / 2.2 % and 1.5 / 5.4 %, staircase2
// 0.6 / 1.3 % and 0.8 / 2.4 %. With Welch's 7 degrees of freedom and the
// Šidák correction over 48 comparisons, a region must differ by several
// of its sd to fail: plastic's base scaled by 1.25 in importance transport
// only (BDPT's light subpaths) failed coffee (both files) and staircase, the
// scenes where plastic covers much of the image; by 1.05 it passed every
// scene. These tests catch a lost or doubled term, not a 5 % one; the BSDF
// tests (tests/core/plastic_test.cpp) hold the 5 %.
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include "core/scene_loader.h"
#include "tests/support/render_helpers.h"
#include "tests/support/repeats.h"

namespace lb::test {
namespace {

struct BitterliScene {
  const char* file;
  int width, height;
  uint64_t pathSpp;
};

SceneFile load(const BitterliScene& c) {
  YAML::Node size = YAML::Load("{film: {width: " + std::to_string(c.width) + ", height: " + std::to_string(c.height) + "}}");
  SceneLoadOptions quiet;
  quiet.quiet = true;
  return loadScene(sourcePath(std::string("scenes/external/") + c.file), size, quiet);
}

void expectAgreement(const BitterliScene& c) { EXPECT_EQ(pathBdptDisagreement(load(c), c.pathSpp, 1e-3), "") << c.file; }

const BitterliScene Scenes[] = {{"veach-ajar/scene.xml", 32, 18, 4096},    {"coffee/scene.xml", 16, 20, 2048},
                                {"coffee/pbrt/scene-v4.pbrt", 16, 20, 2048}, {"staircase/scene.xml", 18, 32, 2048},
                                {"living-room/scene.xml", 32, 18, 2048},   {"staircase2/scene.xml", 24, 24, 2048}};

// The noise quoted at the top: each estimator's relative sd of a region's
// mean over the 8 seeds, its median and largest over regions and channels
// with signal (mean above 1 % of the image's brightest region).
TEST(BitterliScenes, DISABLED_MeasureTheNoiseOfEachComparison) {
  for (const BitterliScene& c : Scenes) {
    SceneFile sf = load(c);
    std::string params = "{max_depth: " + sf.integrator["max_depth"].as<std::string>() + "}";
    for (const char* name : {"path", "bdpt"}) {
      uint64_t spp = std::string(name) == "path" ? c.pathSpp / 8 : c.pathSpp / 32;
      SeedMeans m = seedMeans(sf, {name, params, spp}, 8, 4, 4, 3);
      double brightest = 0;
      for (size_t i = 0; i < m.regions.mean.size(); ++i) brightest = std::max(brightest, m.regions.mean[i]);
      std::vector<double> rel;
      for (size_t i = 0; i < m.regions.mean.size(); ++i)
        if (m.regions.mean[i] > 0.01 * brightest) rel.push_back(std::sqrt(m.regions.varianceOfMean[i]) / m.regions.mean[i]);
      std::sort(rel.begin(), rel.end());
      std::printf("%s %s: relative sd of a region's mean, median %.3f, largest %.3f (%zu of %zu with signal)\n", c.file,
                  name, rel[rel.size() / 2], rel.back(), rel.size(), m.regions.mean.size());
    }
  }
}

TEST(BitterliScenes, PathAndBdptAgreeOnVeachAjar) { expectAgreement({"veach-ajar/scene.xml", 32, 18, 4096}); }
TEST(BitterliScenes, PathAndBdptAgreeOnCoffee) { expectAgreement({"coffee/scene.xml", 16, 20, 2048}); }
TEST(BitterliScenes, PathAndBdptAgreeOnCoffeeFromPbrt) { expectAgreement({"coffee/pbrt/scene-v4.pbrt", 16, 20, 2048}); }
TEST(BitterliScenes, PathAndBdptAgreeOnStaircase) { expectAgreement({"staircase/scene.xml", 18, 32, 2048}); }
TEST(BitterliScenes, PathAndBdptAgreeOnLivingRoom) { expectAgreement({"living-room/scene.xml", 32, 18, 2048}); }
TEST(BitterliScenes, PathAndBdptAgreeOnStaircase2) { expectAgreement({"staircase2/scene.xml", 24, 24, 2048}); }

}  // namespace
}  // namespace lb::test
