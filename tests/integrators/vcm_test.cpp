// Vertex connection and merging (integrators/vcm/): its bpt mode is BDPT, its
// merging modes converge to BDPT's image, its radius follows its formula, and
// it is deterministic across thread counts. Its MIS weights are checked against
// an independent computation in bidirectional_mis_test.cpp.
#include <gtest/gtest.h>
#include <cmath>
#include <cstring>
#include "integrators/vcm/vcm.h"
#include "tests/support/render_helpers.h"

namespace lb::test {
namespace {

constexpr double Alpha = 1e-3;  // family-wise level of each region comparison

TEST(Vcm, BptModeAgreesWithBdpt) {
  // Same estimator (one light subpath per pixel per pass, every connection,
  // BDPT's weights): region means agree within their measured noise.
  for (const char* name : {"cornell-box-spheres", "caustic-glass-sphere"}) {
    SceneFile sf = loadShippedScene(name, 24, 18);
    auto vcm = renderScene(sf, {"vcm", "{mode: bpt, max_depth: 6}", 512, 31});
    auto bdpt = renderScene(sf, {"bdpt", "{max_depth: 6}", 512, 32});
    EXPECT_EQ(compareRegions(regionMeans(*vcm, 3, 3), regionMeans(*bdpt, 3, 3), Alpha), "") << name;
  }
}

TEST(Vcm, RadiusFollowsItsFormula) {
  // r_i = r_1 · i^((α−1)/2) (Georgiev et al. 2012 §5), i = pass + 1: with
  // α = 0.5 the radius halves every 16 passes; α = 1 keeps it.
  SceneFile sf = loadShippedScene("cornell-box", 8, 8);
  Params p(YAML::Load("{radius: 0.2, alpha: 0.5}"), "test", "");
  Vcm vcm(VcmSettings::read(p));
  EXPECT_FLOAT_EQ(vcm.radius(*sf.scene, 0), 0.2f);
  EXPECT_FLOAT_EQ(vcm.radius(*sf.scene, 15), 0.1f);
  EXPECT_FLOAT_EQ(vcm.radius(*sf.scene, 255), 0.05f);
  Params q(YAML::Load("{relative_radius: 0.01, alpha: 1}"), "test", "");
  Vcm fixed(VcmSettings::read(q));
  EXPECT_FLOAT_EQ(fixed.radius(*sf.scene, 0), 0.01f * sf.scene->bounds().radius());
  EXPECT_FLOAT_EQ(fixed.radius(*sf.scene, 99), fixed.radius(*sf.scene, 0));
}

// Mean squared error of `film` against `reference` over all pixels and channels.
double mse(const Film& film, const Image& reference) {
  Image img = film.image();
  double sum = 0;
  for (size_t i = 0; i < img.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) sum += sqr(double(img.pixels[i][c]) - reference.pixels[i][c]);
  return sum / double(3 * img.pixels.size());
}

TEST(Vcm, MergingModesConvergeOnTheGlassSphereCaustic) {
  // Consistency: with the radius shrinking (α = 0.75), the error against a
  // BDPT reference falls from N to 4N iterations, for each merging mode
  // (mean over 4 seeds). The reference's own noise adds the same amount to
  // both, so it cannot make a falling error rise.
  SceneFile sf = loadShippedScene("caustic-glass-sphere", 24, 18);
  Image reference = renderScene(sf, {"bdpt", "{max_depth: 6}", 8192, 41})->image();
  for (const char* mode : {"vcm", "bpm", "ppm"}) {
    std::string params = std::string("{mode: ") + mode + ", max_depth: 6, relative_radius: 0.02}";
    double err[2] = {0, 0};
    for (int k = 0; k < 2; ++k)
      for (uint64_t seed = 1; seed <= 4; ++seed)
        err[k] += mse(*renderScene(sf, {"vcm", params, k == 0 ? 32u : 128u, 100 + seed}), reference) / 4;
    std::printf("%s: MSE against BDPT %.4g after 32 iterations, %.4g after 128 (ratio %.2f)\n", mode, err[0], err[1],
                err[1] / err[0]);
    EXPECT_LT(err[1], err[0]) << mode;
  }
}

TEST(Vcm, EveryModeIsBitIdenticalWithOneAndTwoThreads) {
  SceneFile sf = loadShippedScene("cornell-box-spheres", 40, 40);
  for (std::string mode : {"vcm", "bpm", "ppm", "bpt"}) {
    std::string params = "{mode: " + mode + ", relative_radius: 0.02}";
    Image one = renderScene(sf, {"vcm", params, 4, 42, 1})->image();
    Image two = renderScene(sf, {"vcm", params, 4, 42, 2})->image();
    EXPECT_EQ(std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(Color)), 0) << mode;
  }
}

// The grid and FLANN find the same light vertices and the merges are summed
// in index order either way: identical images, bit for bit (a light vertex
// missed or found twice by either would show). A radius large enough that
// most camera vertices merge with several light vertices.
TEST(Vcm, GridAndFlannLookupsMergeTheSameLightVertices) {
  Params grid(YAML::Load("{lookup: grid}"), "", ""), flann(YAML::Load("{lookup: flann}"), "", "");
  ASSERT_TRUE(VcmSettings::read(grid).gridLookup) << "the two renders below must differ in their lookup";
  ASSERT_FALSE(VcmSettings::read(flann).gridLookup);
  SceneFile sf = loadShippedScene("cornell-box-spheres", 32, 32);
  for (std::string mode : {"vcm", "bpm", "ppm"}) {
    std::string params = "{mode: " + mode + ", relative_radius: 0.05, lookup: ";
    Image grid = renderScene(sf, {"vcm", params + "grid}", 4, 7})->image();
    Image flann = renderScene(sf, {"vcm", params + "flann}", 4, 7})->image();
    EXPECT_EQ(std::memcmp(grid.pixels.data(), flann.pixels.data(), grid.pixels.size() * sizeof(Color)), 0) << mode;
  }
}

}  // namespace
}  // namespace lb::test
