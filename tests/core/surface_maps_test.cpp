// Surface maps (core/textures/surface_maps.h): normal and bump maps against
// normals worked out by hand from their definitions (a tangent-space vector,
// a height field's slope), a flat bump map leaving the normal, opacity's pass
// rate, and path tracing and BDPT agreeing on scenes that use each.
#include <gtest/gtest.h>
#include <cmath>
#include <filesystem>
#include <unistd.h>
#include "core/bsdfs/diffuse.h"
#include "core/error.h"
#include "core/image.h"
#include "core/rng.h"
#include "core/scene_loader.h"
#include "core/textures/surface_maps.h"
#include "tests/support/render_helpers.h"
#include "tests/support/repeats.h"

namespace lb {
namespace {

constexpr std::array<float, 6> Identity = {1, 0, 0, 0, 1, 0};

std::shared_ptr<const Texture> constant(Color c) { return std::make_shared<CheckerboardTexture>(c, c, Identity); }

void expectDirection(const Vec3& got, const Vec3& want, const char* what) {
  Vec3 w = glm::normalize(want);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], w[k], 2e-6) << what << " component " << k;
}

SurfaceInteraction hitWith(Vec3 n, Vec3 dpdu, Vec3 dpdv, Vec2 uv = Vec2(0.4f, 0.3f)) {
  SurfaceInteraction si;
  si.ng = n;
  si.shading = Frame(n);
  si.dpdu = dpdu, si.dpdv = dpdv, si.uv = uv;
  return si;
}

TEST(SurfaceMaps, NormalMapGivesTheTangentSpaceVector) {
  // u runs along +y and v along -x on the plane z = 0: the tangent frame is
  // s = (0, 1, 0), t = n × s = (-1, 0, 0), n = (0, 0, 1). The texel (0.8, 0.4,
  // 0.885) is the vector (0.6, -0.2, 0.77) in it.
  Diffuse m(Color(0.5f));
  m.setSurfaceMaps({constant(Color(0.8f, 0.4f, 0.885f)), nullptr, nullptr});
  SurfaceInteraction si = hitWith(Vec3(0, 0, 1), Vec3(0, 3, 0), Vec3(-2, 0, 0));
  applyShadingMaps(m, si);
  expectDirection(si.shading.n, Vec3(0.2f, 0.6f, 0.77f), "normal");
  // A tangent ∂p/∂u that leaves the plane is projected onto it first.
  si = hitWith(Vec3(0, 0, 1), Vec3(0, 3, 5), Vec3(-2, 0, 0));
  applyShadingMaps(m, si);
  expectDirection(si.shading.n, Vec3(0.2f, 0.6f, 0.77f), "normal, tangent projected");
  // The flat texel (0.5, 0.5, 1) is the surface's own normal.
  m.setSurfaceMaps({constant(Color(0.5f, 0.5f, 1.f)), nullptr, nullptr});
  Vec3 n = glm::normalize(Vec3(0.3f, -0.5f, 0.8f));
  si = hitWith(n, Vec3(1, 0, 0), Vec3(0, 1, 0));
  applyShadingMaps(m, si);
  expectDirection(si.shading.n, n, "flat texel");
}

// A height ramp d = scale · 0.1 · (texel index) along one axis of an 8-texel
// image, read between texel centres where bilinear filtering is linear.
std::shared_ptr<const Texture> ramp(bool alongV) {
  Image im(alongV ? 1 : 8, alongV ? 8 : 1);
  for (int i = 0; i < 8; ++i) im.at(alongV ? 0 : i, alongV ? i : 0) = Color(0.1f * float(i));
  return std::make_shared<ImageTexture>(std::move(im), true, Identity);
}

TEST(SurfaceMaps, BumpMapTiltsTheNormalByTheHeightFieldsSlope) {
  // A plane z = 0 with p = (2u, 2v, 0) displaced along z by d(u, v): the
  // height field z = d(x/2, y/2) has normal (-∂z/∂x, -∂z/∂y, 1). The ramp
  // rises 0.1 per texel, 0.8 per unit u; with bump_scale 0.5, ∂z/∂x = 0.2.
  for (bool alongV : {false, true}) {
    Diffuse m(Color(0.5f));
    Material::SurfaceMaps maps;
    maps.bump = ramp(alongV);
    maps.bumpScale = 0.5f;
    m.setSurfaceMaps(maps);
    Vec2 uv = alongV ? Vec2(0.3f, 0.45f) : Vec2(0.45f, 0.3f);
    SurfaceInteraction si = hitWith(Vec3(0, 0, 1), Vec3(2, 0, 0), Vec3(0, 2, 0), uv);
    applyShadingMaps(m, si);
    expectDirection(si.shading.n, alongV ? Vec3(0, -0.2f, 1) : Vec3(-0.2f, 0, 1), alongV ? "ramp along v" : "ramp along u");
  }
}

TEST(SurfaceMaps, FlatBumpMapLeavesTheShadingNormal) {
  // A constant height moves the surface without turning it, whatever the
  // tangents (here not even perpendicular to the interpolated normal).
  Diffuse m(Color(0.5f));
  Material::SurfaceMaps maps;
  maps.bump = constant(Color(0.7f));
  maps.bumpScale = 3;
  m.setSurfaceMaps(maps);
  Pcg32 rng(7, 1);
  for (int i = 0; i < 1000; ++i) {
    Vec3 n = sampleUniformSphere(Vec2(rng.next1D(), rng.next1D()));
    Vec3 dpdu = 2.f * sampleUniformSphere(Vec2(rng.next1D(), rng.next1D()));
    Vec3 dpdv = glm::cross(n, dpdu) + 0.3f * dpdu;
    if (glm::length(glm::cross(dpdu - n * glm::dot(n, dpdu), dpdv - n * glm::dot(n, dpdv))) < 1e-2f) continue;
    SurfaceInteraction si = hitWith(n, dpdu, dpdv, Vec2(rng.next1D(), rng.next1D()));
    applyShadingMaps(m, si);
    for (int k = 0; k < 3; ++k) ASSERT_NEAR(si.shading.n[k], n[k], 1e-5) << "hit " << i;
  }
}

TEST(SurfaceMaps, OpacityLetsThroughTheShareOneMinusAlpha) {
  // Over rays, a surface of opacity α is passed with probability 1 − α, and
  // two surfaces on one ray decide independently: (1 − α)² for both. Each
  // count is within 5 binomial standard deviations.
  Pcg32 rng(11, 1);
  const int n = 200000;
  for (float alpha : {0.1f, 0.5f, 0.85f}) {
    int one = 0, both = 0;
    for (int i = 0; i < n; ++i) {
      Vec3 o(rng.next1D(), rng.next1D(), rng.next1D());
      Vec3 d = sampleUniformSphere(Vec2(rng.next1D(), rng.next1D()));
      bool a = passesThrough(alpha, o, d, 3, 17), b = passesThrough(alpha, o, d, 3, 18);
      one += a, both += a && b;
    }
    for (auto [count, p] : {std::pair{one, 1.0 - alpha}, std::pair{both, (1.0 - alpha) * (1.0 - alpha)}})
      EXPECT_NEAR(count, n * p, 5 * std::sqrt(n * p * (1 - p))) << "alpha " << alpha;
  }
  EXPECT_FALSE(passesThrough(1.f, Vec3(0.f), Vec3(0, 0, 1), 0, 0));
  EXPECT_TRUE(passesThrough(0.f, Vec3(0.f), Vec3(0, 0, 1), 0, 0));
  // A texture's opacity is its luminance (Mitsuba's mask), clamped to [0, 1].
  EXPECT_NEAR(opacityOf(Color(0.9f, 0.1f, 0.4f)), 0.212671 * 0.9 + 0.715160 * 0.1 + 0.072169 * 0.4, 1e-4);
  EXPECT_EQ(opacityOf(Color(2.f)), 1.f);
}

// The camera looks through a black quad of opacity α at an emitter of
// radiance 2 filling the view: every pixel's expected value is (1 − α)·2, the
// rays that pass. A uniform opacity number and a uniform opacity texture
// (its luminance) alike.
TEST(SurfaceMaps, ABlackMaskedQuadShowsTheShareOfTheEmitterItLetsThrough) {
  for (auto [opacity, alpha] : {std::pair<std::string, double>{"0.3", 0.3},
                                {"{type: checkerboard, color0: [0.9, 0.1, 0.4], color1: [0.9, 0.1, 0.4]}",
                                 0.212671 * 0.9 + 0.715160 * 0.1 + 0.072169 * 0.4}}) {
    SceneFile f = loadSceneFromString(
        "camera: {position: [0, 0, 3], look_at: [0, 0, 0], fov: 30}\n"
        "film: {width: 16, height: 16}\n"
        "materials:\n"
        "  leaf: {type: diffuse, albedo: 0, opacity: " + opacity + "}\n"
        "shapes:\n"
        "  - {type: rectangle, material: leaf, transform: {scale: 3}}\n"
        "  - {type: rectangle, material: none, emission: 2, transform: {scale: 10, translate: [0, 0, -1]}}\n",
        "mask.yaml");
    test::RenderSpec spec;
    spec.spp = 64;
    auto film = test::renderScene(f, spec);
    for (int c = 0; c < 3; ++c) EXPECT_TRUE(test::meanMatches(*film, (1 - alpha) * 2, 1e-3, c)) << opacity;
  }
}

TEST(SurfaceMaps, OpacityIsRefusedOnSpheresAndEmitters) {
  const std::string head = "camera: {position: [0, 0, 3], look_at: [0, 0, 0]}\nmaterials:\n  leaf: {opacity: 0.5}\nshapes:\n";
  EXPECT_THROW(loadSceneFromString(head + "  - {type: sphere, material: leaf}\n", "s.yaml"), ConfigError);
  EXPECT_THROW(loadSceneFromString(head + "  - {type: rectangle, material: leaf, emission: 1}\n", "e.yaml"), ConfigError);
  for (const char* bad : {"{opacity: 1.5}", "{opacity: -0.1}", "{bump_scale: 2}",
                          "{bump_map: {type: checkerboard}, normal_map: {type: checkerboard}}"})
    EXPECT_THROW(loadSceneFromString(std::string("camera: {position: [0, 0, 3], look_at: [0, 0, 0]}\nmaterials:\n  m: ") +
                                         bad + "\nshapes:\n  - {type: rectangle, material: m}\n",
                                     "bad.yaml"),
                 ConfigError)
        << bad;
}

// Through a scene file and Scene::intersect: a rectangle's uvs run along its
// x and y (dpdu = (2s, 0, 0)), so the normal map's tangent frame is the
// world's; the hit's shading normal is the map's vector.
TEST(SurfaceMaps, HitsOnANormalMappedRectangleCarryTheMapsNormal) {
  SceneFile f = loadSceneFromString(
      "camera: {position: [0, 0, 3], look_at: [0, 0, 0]}\n"
      "materials:\n"
      "  m: {type: diffuse, normal_map: {type: checkerboard, color0: [0.8, 0.4, 0.885], color1: [0.8, 0.4, 0.885]}}\n"
      "shapes:\n"
      "  - {type: rectangle, material: m, transform: {scale: 2}}\n",
      "n.yaml");
  SurfaceInteraction si;
  ASSERT_TRUE(f.scene->intersect(Ray{Vec3(0.3f, 0.2f, 2), Vec3(0, 0, -1), Infinity}, si));
  expectDirection(si.shading.n, Vec3(0.6f, -0.2f, 0.77f), "shading normal");
  EXPECT_NEAR(si.ng.z, 1, 1e-6) << "the geometric normal is the surface's";
  // A sphere's u = φ/2π: at (0, −1, 0), where n = (0, −1, 0), ∂p/∂φ points
  // along +x, so s = (1, 0, 0) and t = n × s = (0, 0, 1).
  SceneFile g = loadSceneFromString(
      "camera: {position: [0, -3, 0], look_at: [0, 0, 0], up: [0, 0, 1]}\n"
      "materials:\n"
      "  m: {type: diffuse, normal_map: {type: checkerboard, color0: [0.8, 0.4, 0.885], color1: [0.8, 0.4, 0.885]}}\n"
      "shapes:\n"
      "  - {type: sphere, material: m}\n",
      "s.yaml");
  ASSERT_TRUE(g.scene->intersect(Ray{Vec3(0, -3, 0), Vec3(0, 1, 0), Infinity}, si));
  expectDirection(si.shading.n, 0.6f * Vec3(1, 0, 0) - 0.2f * Vec3(0, 0, 1) + 0.77f * Vec3(0, -1, 0), "sphere");
}

std::string tempFolder() {
  auto dir = std::filesystem::temp_directory_path() / ("lb-surface-maps-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  return dir.string();
}

// A room lit from above: a bump-mapped back wall (ridges from an EXR height
// image), a normal-mapped floor (two tilted normals in a checkerboard) and,
// between the light and the floor, a leaf of checkerboard opacity (holes and
// leaf) beside a pane of opacity 0.5 that the camera sees.
std::string room(const std::string& bump = "{type: image, file: ridges.exr, uv_transform: [3, 0, 0, 0, 3, 0]}") {
  std::string s =
      "camera: {position: [0, 1, 3.5], look_at: [0, 0.8, 0], fov: 50}\n"
      "film: {width: 32, height: 32}\n"
      "integrator: {name: path, max_depth: 6}\n"
      "materials:\n"
      "  white: {type: diffuse, albedo: 0.7}\n";
  s += "  wall: {type: diffuse, albedo: 0.7, bump_map: " + bump + ", bump_scale: 0.3}\n"
         "  floor: {type: conductor, roughness: 0.3, tint: 0.8, normal_map: {type: checkerboard, color0: [0.75, 0.5, 0.93],"
         " color1: [0.35, 0.7, 0.88], uv_transform: [4, 0, 0, 0, 4, 0]}}\n"
         "  leaf: {type: diffuse, albedo: [0.2, 0.6, 0.1], opacity: {type: checkerboard, color0: 0, color1: 1,"
         " uv_transform: [5, 0, 0, 0, 5, 0]}}\n"
         "  pane: {type: diffuse, albedo: 0.5, opacity: 0.5}\n";
  s += "shapes:\n"
       "  - {type: rectangle, material: floor, transform: {scale: 2, rotate_x: -90}}\n"
       "  - {type: rectangle, material: wall, transform: {scale: 2, translate: [0, 1, -2]}}\n"
       "  - {type: rectangle, material: white, transform: {scale: 2, rotate_y: 90, translate: [-2, 1, 0]}}\n"
       "  - {type: rectangle, material: leaf, transform: {scale: 0.6, rotate_x: -60, translate: [0.3, 1.3, 0]}}\n"
       "  - {type: rectangle, material: pane, transform: {scale: 0.4, translate: [-0.7, 0.6, 0.8]}}\n"
       "  - {type: rectangle, material: none, emission: 6, transform: {scale: 0.4, rotate_x: 90, translate: [0, 2, 0]}}\n";
  return s;
}

SceneFile loadRoom(const std::string& yaml) {
  std::string dir = tempFolder();
  // Ridges: a height that is a sine across 16 texels, bilinearly filtered.
  Image ridges(16, 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) ridges.at(x, y) = Color(0.5f + 0.5f * std::sin(2 * Pi * float(x) / 16));
  writeExr(dir + "/ridges.exr", ridges);
  return loadSceneFromString(yaml, dir + "/room.yaml");
}

// Path tracing and BDPT agree on the room with every map: the perturbed
// normals enter the adjoint correction of BDPT's light subpaths
// (core/bsdfs/bsdf.h), and the masks its shadow rays, connections and light
// paths, as they enter path tracing's.
TEST(SurfaceMaps, PathAndBdptAgreeOnARoomWithBumpNormalAndOpacityMaps) {
  SceneFile f = loadRoom(room());
  std::string failures = test::pathBdptDisagreement(f, 256, 1e-3, 6);
  EXPECT_TRUE(failures.empty()) << failures;
}

// A bump map of one height changes nothing: the room with a constant bump
// map on the wall renders as the room without one (other seeds, z-tests).
TEST(SurfaceMaps, AFlatBumpMapRendersAsNoBumpMap) {
  std::string flat = room("{type: checkerboard, color0: 0.6, color1: 0.6}");
  std::string plain = flat;
  plain.replace(plain.find(", bump_map: {type: checkerboard, color0: 0.6, color1: 0.6}, bump_scale: 0.3"),
                std::string(", bump_map: {type: checkerboard, color0: 0.6, color1: 0.6}, bump_scale: 0.3").size(), "");
  test::RenderSpec spec;
  spec.spp = 512;
  spec.seed = 3;
  auto withMap = test::renderScene(loadRoom(flat), spec);
  spec.seed = 4;
  auto without = test::renderScene(loadRoom(plain), spec);
  std::string failures = test::compareRegions(test::regionMeans(*withMap, 4, 4), test::regionMeans(*without, 4, 4), 1e-3);
  EXPECT_TRUE(failures.empty()) << failures;
}

}  // namespace
}  // namespace lb
