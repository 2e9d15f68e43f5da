// Textures (core/textures/texture.h): lookups against values worked out from
// the definitions (texel centres, bilinear weights, repetition, the
// checkerboard's cells), PNG decoding, the OBJ v flip, the box and disk
// parametrisations, and a textured material against the same constant colour.
#include <gtest/gtest.h>
#include "core/image_input.h"
#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include "core/bsdfs/bsdf.h"
#include "core/error.h"
#include "core/image.h"
#include "core/mesh_io.h"
#include "core/scene_loader.h"
#include "tests/support/render_helpers.h"

namespace lb {
namespace {

constexpr std::array<float, 6> Identity = {1, 0, 0, 0, 1, 0};

// 2 × 2 texels: top row (y = 0) red, green; bottom row blue, white.
Image quad() {
  Image im(2, 2);
  im.at(0, 0) = Color(1, 0, 0), im.at(1, 0) = Color(0, 1, 0);
  im.at(0, 1) = Color(0, 0, 1), im.at(1, 1) = Color(1, 1, 1);
  return im;
}

void expectColor(Color got, Color want, const char* what) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-6) << what << " channel " << c;
}

TEST(Texture, ImageTexelCentresAndBilinearWeights) {
  ImageTexture t(quad(), true, Identity);
  // Texel (x, y) is centred at ((x + ½)/W, (y + ½)/H); v = 0 is the top row.
  expectColor(t.eval(Vec2(0.25f, 0.25f)), Color(1, 0, 0), "top-left centre");
  expectColor(t.eval(Vec2(0.75f, 0.75f)), Color(1, 1, 1), "bottom-right centre");
  // Midway between all four centres: their mean.
  expectColor(t.eval(Vec2(0.5f, 0.5f)), Color(0.5f, 0.5f, 0.5f), "centre of the image");
  // A quarter of the way from the top-left centre to the top-right one.
  expectColor(t.eval(Vec2(0.375f, 0.25f)), Color(0.75f, 0.25f, 0), "along the top row");
  // u = 0 lies halfway between the last column and the first (repetition).
  expectColor(t.eval(Vec2(0.f, 0.25f)), Color(0.5f, 0.5f, 0), "across the seam");
  expectColor(t.eval(Vec2(3.25f, -1.75f)), Color(1, 0, 0), "a whole period away");
  ImageTexture nearest(quad(), false, Identity);
  expectColor(nearest.eval(Vec2(0.49f, 0.51f)), Color(0, 0, 1), "nearest: bottom-left texel");
  expectColor(t.mean(), Color(0.5f, 0.5f, 0.5f), "mean");
  expectColor(t.maxValue(), Color(1, 1, 1), "max");
}

TEST(Texture, UvTransformIsAppliedBeforeTheLookup) {
  // u' = 0.5 v + 0.25, v' = 2 u: (0.2, 1) → (0.75, 0.4) → nearest texel (1, 0), green.
  ImageTexture t(quad(), false, {0, 0.5f, 0.25f, 2, 0, 0});
  expectColor(t.eval(Vec2(0.2f, 1.f)), Color(0, 1, 0), "transformed lookup");
}

TEST(Texture, CheckerboardCells) {
  CheckerboardTexture t(Color(0.8f), Color(0.1f), {4, 0, 0, 0, 4, 0});
  // Scaled by 4: (0.05, 0.05) → (0.2, 0.2), both fractions below ½: color0.
  expectColor(t.eval(Vec2(0.05f, 0.05f)), Color(0.8f), "both low");
  expectColor(t.eval(Vec2(0.15f, 0.05f)), Color(0.1f), "u high, v low");
  expectColor(t.eval(Vec2(0.15f, 0.15f)), Color(0.8f), "both high");
  expectColor(t.eval(Vec2(-0.05f, 0.05f)), Color(0.1f), "negative u repeats (frac 0.8)");
  expectColor(t.mean(), Color(0.45f), "mean");
}

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("lb-texture-" + std::to_string(getpid()) + "-" + name)).string();
}

TEST(Texture, PngIsDecodedFromSrgbUnlessRaw) {
  // writePng encodes with the sRGB curve; 0.5 linear is stored as 188 (0.7354).
  Image im(1, 1);
  im.at(0, 0) = Color(0.5f, 0.f, 1.f);
  std::string path = tempPath("half.png");
  writePng(path, im);
  Image linear = readImageFile(path, true).rgb, raw = readImageFile(path, false).rgb;
  std::filesystem::remove(path);
  // The stored byte, decoded by the sRGB formula written out here.
  double stored = 188 / 255.0, decoded = std::pow((stored + 0.055) / 1.055, 2.4);
  EXPECT_NEAR(raw.at(0, 0).r, stored, 1e-6);
  EXPECT_NEAR(linear.at(0, 0).r, decoded, 1e-6);
  EXPECT_NEAR(linear.at(0, 0).r, 0.5, 0.003);  // one 8-bit step
  EXPECT_EQ(linear.at(0, 0).g, 0.f);
  EXPECT_EQ(linear.at(0, 0).b, 1.f);
}

TEST(Texture, ObjTextureCoordinatesAreFlippedToImageRows) {
  std::string path = tempPath("uv.obj");
  std::ofstream(path) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.1 0.25\nvt 0.2 0.5\nvt 0.3 1\nf 1/1 2/2 3/3\n";
  MeshLoadResult r = loadMesh(path, Mat4(1.f), false);
  std::filesystem::remove(path);
  ASSERT_EQ(r.mesh.uvs.size(), 3u);
  auto uvAt = [&](Vec3 p) {
    for (size_t i = 0; i < r.mesh.positions.size(); ++i)
      if (r.mesh.positions[i] == p) return r.mesh.uvs[i];
    ADD_FAILURE() << "no vertex at " << p.x << " " << p.y;
    return Vec2(-1.f);
  };
  // OBJ's v = 0.25 is a quarter up from the bottom: 0.75 down from the top.
  EXPECT_FLOAT_EQ(uvAt(Vec3(0, 0, 0)).y, 0.75f);
  EXPECT_FLOAT_EQ(uvAt(Vec3(0, 1, 0)).y, 0.f);
  EXPECT_FLOAT_EQ(uvAt(Vec3(1, 0, 0)).x, 0.2f);
}

TEST(Texture, AnObjTextureSeamIsFoundAndNamedByLine) {
  // Two triangles share the edge (1,0)-(0,1) but give it different vt: a
  // seam, which one uv per vertex cannot represent. Said with its line.
  std::string dir = tempPath("seam");
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/seam.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                      "vt 0 0\nvt 0.5 0\nvt 0 0.5\nvt 1 1\nvt 0.6 0.9\nvt 0.9 0.6\n"
                                      "f 1/1 2/2 3/3\nf 2/6 4/4 3/5\n";
  MeshLoadResult r = loadMesh(dir + "/seam.obj", Mat4(1.f), false);
  EXPECT_NE(r.mesh.uvSeam.find("seam.obj:12:"), std::string::npos) << r.mesh.uvSeam;
  // The same vertices with the same vt on both faces: no seam.
  std::ofstream(dir + "/seamless.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\n"
                                          "f 1/1 2/2 3/3\nf 2/2 4/4 3/3\n";
  EXPECT_TRUE(loadMesh(dir + "/seamless.obj", Mat4(1.f), false).mesh.uvSeam.empty());
  std::filesystem::remove_all(dir);
}

// The material seen by a camera ray through the image centre.
SurfaceInteraction centreHit(const SceneFile& f) {
  SurfaceInteraction si;
  EXPECT_TRUE(f.scene->intersect(f.scene->camera.generateRay(Vec2(8, 8)), si));
  return si;
}

std::string planeScene(const std::string& shape, const std::string& material) {
  return "camera: {position: [0, 0, 5], look_at: [0, 0, 0], fov: 30}\nfilm: {width: 16, height: 16}\n"
         "materials:\n  m: " + material + "\nshapes:\n  - " + shape + "\n";
}

TEST(Texture, ATexturedMaterialScalesFOnly) {
  // A constant texture c on albedo 1 is the albedo c, in f, pdf and weight alike.
  SceneFile a = loadSceneFromString(planeScene("{type: rectangle, material: m}",
      "{type: diffuse, albedo: 1, texture: {type: checkerboard, color0: 0.3, color1: 0.3}}"), "a.yaml");
  SceneFile b = loadSceneFromString(planeScene("{type: rectangle, material: m}", "{type: diffuse, albedo: 0.3}"), "b.yaml");
  SurfaceInteraction sa = centreHit(a), sb = centreHit(b);
  BSDF fa(sa), fb(sb);
  Vec3 wo = glm::normalize(Vec3(0.2f, 0.1f, 1)), wi = glm::normalize(Vec3(-0.5f, 0.3f, 0.8f));
  BSDFEval ea = fa.eval(wo, wi, TransportMode::Radiance), eb = fb.eval(wo, wi, TransportMode::Radiance);
  EXPECT_NEAR(ea.f.g, eb.f.g, 1e-7);
  EXPECT_EQ(ea.pdf, eb.pdf);
  auto xa = fa.sample(wo, 0.3f, Vec2(0.4f, 0.7f), TransportMode::Importance);
  auto xb = fb.sample(wo, 0.3f, Vec2(0.4f, 0.7f), TransportMode::Importance);
  ASSERT_TRUE(xa && xb);
  EXPECT_EQ(xa->wi, xb->wi);
  EXPECT_NEAR(xa->weight.r, xb->weight.r, 1e-6);
}

TEST(Texture, EnergyIsCheckedOnTheTexturesLargestValue) {
  EXPECT_THROW(loadSceneFromString(planeScene("{type: rectangle, material: m}",
      "{type: diffuse, albedo: 0.9, texture: {type: checkerboard, color0: 1.2, color1: 0.1}}"), "c.yaml"), ConfigError);
  EXPECT_THROW(loadSceneFromString(planeScene("{type: rectangle, material: m}",
      "{type: dielectric, texture: {type: checkerboard}}"), "d.yaml"), ConfigError);
  EXPECT_THROW(loadSceneFromString(planeScene("{type: rectangle, material: m}",
      "{type: diffuse, texture: {type: image, file: missing.png}}"), "e.yaml"), ConfigError);
}

TEST(Texture, BoxFaceUvIsMitsubasCubes) {
  SceneFile f = loadSceneFromString(planeScene("{type: box, material: m}", "{type: diffuse}"), "box.yaml");
  // Mitsuba's +z face has corners (1,-1), (1,1), (-1,1), (-1,-1) at uv (0,1),
  // (1,1), (1,0), (0,0): u = (y + 1)/2, v = (x + 1)/2.
  SurfaceInteraction si;
  ASSERT_TRUE(f.scene->intersect(Ray{Vec3(0.5f, -0.5f, 3), Vec3(0, 0, -1), Infinity}, si));
  EXPECT_NEAR(si.uv.x, 0.25f, 1e-6);
  EXPECT_NEAR(si.uv.y, 0.75f, 1e-6);
}

TEST(Texture, BoxFacesEachSpanTheUnitSquareAndFaceOutwards) {
  SceneFile f = loadSceneFromString(planeScene("{type: box, material: m}", "{type: diffuse}"), "box.yaml");
  // Rays from outside towards each face's centre: the hit's normal points back
  // at the ray's origin, and the face centre has uv (½, ½).
  for (int axis = 0; axis < 3; ++axis)
    for (float sign : {-1.f, 1.f}) {
      Vec3 o(0.1f, 0.2f, 0.3f);  // off-centre, so uv must be interpolated
      o[axis] = 3 * sign;
      Vec3 target(0.f);
      Ray ray{o, glm::normalize(target - o + Vec3(0.f)), Infinity};
      SurfaceInteraction si;
      ASSERT_TRUE(f.scene->intersect(ray, si));
      EXPECT_GT(glm::dot(si.ng, o - si.p), 0) << "axis " << axis << " sign " << sign;
      EXPECT_GE(si.uv.x, 0.f);
      EXPECT_LE(si.uv.x, 1.f);
      EXPECT_GE(si.uv.y, 0.f);
      EXPECT_LE(si.uv.y, 1.f);
    }
}

TEST(Texture, DiskIsARegularPolygonFacingZWithPolarUv) {
  SceneFile f = loadSceneFromString(planeScene("{type: disk, segments: 64, material: m}", "{type: diffuse}"), "disk.yaml");
  // Area of the regular 64-gon inscribed in the unit circle.
  EXPECT_NEAR(f.scene->shapes()[0].area(), 32 * std::sin(2 * Pi / 64), 1e-4);
  SurfaceInteraction si;
  Ray ray{Vec3(0.5f, 0.5f, 2), Vec3(0, 0, -1), Infinity};
  ASSERT_TRUE(f.scene->intersect(ray, si));
  EXPECT_NEAR(si.ng.z, 1, 1e-6);
  // u = r and v = φ/2π up to the fan's linear interpolation: r is off by the
  // chord's sag (1 − cos(π/64) < 1.3e-3), v by at most half a wedge, 1/128.
  EXPECT_NEAR(si.uv.x, std::sqrt(0.5), 1.3e-3);
  EXPECT_NEAR(si.uv.y, 0.125, 1.0 / 128);
}

}  // namespace
}  // namespace lb

namespace lb {
namespace {

// End to end: a checkerboard floor seen partly through a thin dielectric
// pane, lit by an area light. Path tracing and BDPT must agree region by
// region (z-tests): the texture enters both transport directions (BDPT's
// light subpaths evaluate it in importance mode) and the pane's two lobes
// are sampled by both.
TEST(Texture, PathAndBdptAgreeOnATexturedFloorBehindAThinPane) {
  SceneFile f = loadSceneFromString(
      "camera: {position: [0, 1.5, 4], look_at: [0, 0, 0], fov: 45}\n"
      "film: {width: 32, height: 32}\n"
      "materials:\n"
      "  floor: {type: diffuse, albedo: 1, texture: {type: checkerboard, color0: 0.8, color1: 0.15, uv_transform: [3, 0, 0, 0, 3, 0]}}\n"
      "  pane: {type: thin_dielectric, ior: 1.5}\n"
      "  grey: {type: diffuse, albedo: 0.5}\n"
      "shapes:\n"
      "  - {type: rectangle, material: floor, transform: {scale: 2, rotate_x: -90}}\n"
      "  - {type: rectangle, material: pane, transform: {scale: [0.8, 0.5, 1], translate: [0.4, 0.5, 1]}}\n"
      "  - {type: rectangle, material: grey, transform: {scale: 2, translate: [0, 1, -2]}}\n"
      "  - {type: rectangle, material: none, emission: 4, transform: {scale: 0.5, rotate_x: 90, translate: [0, 2.5, 0]}}\n",
      "textured.yaml");
  test::RenderSpec spec;
  spec.spp = 1024;
  spec.seed = 5;
  auto path = test::renderScene(f, spec);
  spec.integrator = "bdpt";
  spec.spp = 256;
  spec.seed = 6;
  auto bdpt = test::renderScene(f, spec);
  std::string failures = test::compareRegions(test::regionMeans(*path, 4, 4), test::regionMeans(*bdpt, 4, 4), 1e-3);
  EXPECT_TRUE(failures.empty()) << failures;
}

}  // namespace
}  // namespace lb
