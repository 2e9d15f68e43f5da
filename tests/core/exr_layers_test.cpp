// Layered EXRs (issue 15): the main image, named layers of 1 or 3 channels and
// string metadata in the header, read back exactly; and the first-hit AOVs
// against a computation from the Cornell box's geometry.
#include <gtest/gtest.h>
#include <filesystem>
#include "core/aov.h"
#include "core/image.h"
#include "tests/support/render_helpers.h"

namespace lb {
namespace {

Image ramp(int w, int h, float scale) {
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.at(x, y) = Color(scale * x, scale * y + 0.5f, scale * (x + y) - 1.f);
  return img;
}

TEST(ExrLayers, LayersAndMetadataReadBackExactly) {
  auto path = (std::filesystem::temp_directory_path() / ("layers-" + std::to_string(::getpid()) + ".exr")).string();
  Image main = ramp(7, 5, 0.25f), albedo = ramp(7, 5, 0.125f), normal = ramp(7, 5, -0.5f), depth = ramp(7, 5, 3.f);
  writeExr(path, main,
           {{"albedo", {"R", "G", "B"}, albedo}, {"normal", {"X", "Y", "Z"}, normal}, {"depth", {"Z"}, depth}},
           {{"lightbench/integrator", "bdpt"}, {"lightbench/spp", "64"}});
  auto same = [](const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.pixels == b.pixels;
  };
  EXPECT_TRUE(same(readExr(path), main)) << "R, G, B stay the main image";
  EXPECT_TRUE(same(readExrLayer(path, "albedo"), albedo));
  EXPECT_TRUE(same(readExrLayer(path, "normal"), normal)) << "X, Y, Z in that order, not alphabetical";
  Image d = readExrLayer(path, "depth");
  for (size_t i = 0; i < d.pixels.size(); ++i) EXPECT_EQ(d.pixels[i], Color(depth.pixels[i].r));
  auto attributes = readExrAttributes(path);
  EXPECT_EQ(attributes["lightbench/integrator"], "bdpt");
  EXPECT_EQ(attributes["lightbench/spp"], "64");
  EXPECT_THROW(readExrLayer(path, "missing"), std::runtime_error);
  EXPECT_THROW(writeExr(path, main, {{"small", {"R", "G", "B"}, Image(3, 3)}}, {}), std::runtime_error);
  EXPECT_TRUE(same(readExr(path), main)) << "a failed write leaves the earlier file";
  std::filesystem::remove(path);
}

// The back wall of the Cornell box (z = -1, white diffuse, albedo 0.73) seen
// above the tall box: albedo, normal and depth from the wall's plane.
TEST(FirstHitImages, MatchTheBackWallsGeometry) {
  SceneFile sf = test::loadShippedScene("cornell-box", 64, 64);
  const Camera& cam = sf.scene->camera;
  FirstHitImages aov = renderFirstHitImages(*sf.scene, 16, 1);
  int checked = 0;
  for (int y = 14; y < 26; ++y)  // above the tall box, below the ceiling
    for (int x = 28; x < 36; ++x) {
      // The plane z = -1 along the rays through the pixel's corners: the
      // mean distance of rays through the pixel lies between their extremes.
      float lo = Infinity, hi = 0;
      for (Vec2 corner : {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1), Vec2(1, 1)}) {
        Ray r = cam.generateRay(Vec2(float(x), float(y)) + corner);
        float t = (-1.f - r.o.z) / r.d.z;
        lo = std::min(lo, t), hi = std::max(hi, t);
      }
      EXPECT_GE(aov.depth.at(x, y).r, lo * (1 - 1e-6f)) << x << "," << y;
      EXPECT_LE(aov.depth.at(x, y).r, hi * (1 + 1e-6f)) << x << "," << y;
      // Cosine-sampled Lambertian: f cos / pdf is the albedo for every sample.
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(aov.albedo.at(x, y)[c], 0.73f, 1e-5f) << x << "," << y;
      EXPECT_NEAR(aov.normal.at(x, y).z, 1.f, 1e-5f);
      EXPECT_NEAR(aov.normal.at(x, y).x, 0.f, 1e-5f);
      ++checked;
    }
  EXPECT_EQ(checked, 96);
  // The red wall (x = -1): its albedo and normal +x.
  EXPECT_NEAR(aov.albedo.at(1, 32).r, 0.65f, 1e-5f);
  EXPECT_NEAR(aov.normal.at(1, 32).x, 1.f, 1e-5f);
}

}  // namespace
}  // namespace lb
