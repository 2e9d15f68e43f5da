// Light tracing and BDPT against the path tracer (testing.md §3–4): per-region
// z-tests with variances from the films, Šidák-corrected; analytic radiance;
// the shading-normal adjoint; per-strategy images; determinism.
#include <gtest/gtest.h>
#include <cstring>
#include <fstream>
#include "integrators/bdpt/bdpt.h"
#include "integrators/bidirectional/subpaths.h"
#include "integrators/bidirectional/verification.h"
#include "integrators/render_loop.h"
#include "tests/support/render_helpers.h"

namespace lb::test {
namespace {

constexpr double Alpha = 0.01;

struct Case {
  std::string scene;
  int width, height;
  uint64_t pathSpp, lightSpp, bdptSpp;
};

// BDPT against PT everywhere; LT against BDPT on pixels whose primary hit is
// diffuse. Why there: LT cannot sample L…S E paths (a specular surface seen
// through the pinhole), and through a near-specular lobe (Veach's α = 0.005
// plate) its connections are so heavy-tailed that the sample variance
// understates the true one; PT in turn finds caustics (the mirror sphere's on
// the red wall) only by chance. BDPT, which contains both, is the fair
// reference for LT. max_depth 8 for all: long enough for the glass sphere's
// caustic (L S S D E needs 4 segments) and several interreflections.
void expectAgreement(const SceneFile& sf, const Case& c) {
  auto pt = renderScene(sf, {"path", "{max_depth: 8}", c.pathSpp, 101});
  auto lt = renderScene(sf, {"light", "{max_depth: 8}", c.lightSpp, 102});
  auto bd = renderScene(sf, {"bdpt", "{max_depth: 8}", c.bdptSpp, 103});
  std::vector<bool> mask = diffusePrimaryHits(*sf.scene);
  EXPECT_EQ(compareRegions(regionMeans(*lt, 4, 4, &mask), regionMeans(*bd, 4, 4, &mask), Alpha / 2), "")
      << c.scene << ": light tracing vs BDPT";
  EXPECT_EQ(compareRegions(regionMeans(*bd, 4, 4), regionMeans(*pt, 4, 4), Alpha / 2), "")
      << c.scene << ": BDPT vs path tracing";
  EXPECT_EQ(lt->nonFiniteCount() + bd->nonFiniteCount(), 0u);
}
void expectAgreement(const Case& c) { expectAgreement(loadShippedScene(c.scene, c.width, c.height), c); }

TEST(Bidirectional, AgreeOnDiffuseCornellBox) { expectAgreement({"cornell-box", 32, 32, 512, 512, 256}); }
TEST(Bidirectional, AgreeOnCornellBoxWithMirrorAndGlassSpheres) {
  expectAgreement({"cornell-box-spheres", 32, 32, 1024, 512, 256});
}
TEST(Bidirectional, AgreeOnVeachMisScene) { expectAgreement({"veach-mis", 40, 25, 1024, 1024, 512}); }
// Mitsuba's plastics (core/bsdfs/plastic.h) in the Cornell box: a smooth
// coating (a delta lobe beside a diffuse one: light and BDPT connect to its
// base, only sampling finds its mirror) on the left sphere, a rough nonlinear
// one with separable masking on the right, and a checkerboard under a rough
// coating on the floor (only the base is textured).
TEST(Bidirectional, AgreeOnSmoothRoughAndTexturedPlastics) {
  SceneFile sf = loadSceneFromString(
      "camera: {position: [0, 1, 4.0], look_at: [0, 1, 0], fov: 36.5}\n"
      "film: {width: 32, height: 32}\n"
      "materials:\n"
      "  white: {type: diffuse, albedo: 0.73}\n"
      "  red: {type: diffuse, albedo: [0.65, 0.05, 0.05]}\n"
      "  smooth: {type: plastic, albedo: [0.1, 0.3, 0.8]}\n"
      "  rough: {type: plastic, albedo: [0.8, 0.4, 0.1], roughness: 0.2, distribution: beckmann,\n"
      "          masking: separable, nonlinear: true}\n"
      "  floor: {type: plastic, roughness: 0.3, albedo: 1,\n"
      "          texture: {type: checkerboard, color0: 0.2, color1: 0.8, uv_transform: [4, 0, 0, 0, 4, 0]}}\n"
      "shapes:\n"
      "  - {type: rectangle, material: floor, transform: {rotate_x: -90}}\n"
      "  - {type: rectangle, material: white, transform: {rotate_x: 90, translate: [0, 2, 0]}}\n"
      "  - {type: rectangle, material: white, transform: {translate: [0, 1, -1]}}\n"
      "  - {type: rectangle, material: red, transform: {rotate_y: 90, translate: [-1, 1, 0]}}\n"
      "  - {type: rectangle, material: white, transform: {rotate_y: -90, translate: [1, 1, 0]}}\n"
      "  - {type: rectangle, material: white, emission: [17, 12, 4],\n"
      "     transform: {scale: [0.25, 0.2, 1], rotate_x: 90, translate: [0, 1.98, 0]}}\n"
      "  - {type: sphere, material: smooth, center: [-0.42, 0.35, -0.35], radius: 0.35}\n"
      "  - {type: sphere, material: rough, center: [0.42, 0.35, 0.3], radius: 0.35}\n"
      "integrator: {name: path}\n",
      "plastics.yaml");
  expectAgreement(sf, {"plastics", 32, 32, 1024, 512, 256});
}

// With a point light the path tracer cannot sample paths whose last bounce
// before the light is delta (L S … E: a mirror seen from the light); this
// scene has no delta surface, so all three estimate the same image.
TEST(Bidirectional, AgreeOnPointLightScene) { expectAgreement({"point-light", 32, 24, 512, 512, 256}); }

TEST(Bidirectional, AgreeUnderDirectionalSpotAndEnvironmentLights) {
  // Light tracing and BDPT with every other light type, against PT (which
  // samples all of them by NEE here). The environment is seen directly in
  // some pixels; the diffuse-hit mask leaves those out, since LT cannot
  // estimate a directly visible environment. All surfaces are diffuse: with a
  // glossy sphere the spot light casts a glossy caustic (L G D E) that PT
  // reaches only by a BSDF bounce onto the sphere and NEE there — correct but
  // so heavy-tailed that its sample variance understates the truth.
  const std::string geometry =
      "camera: {position: [0, 2, 5], look_at: [0, 0.4, 0], fov: 40}\n"
      "film: {width: 32, height: 24}\n"
      "materials: {floor: {type: diffuse, albedo: 0.6}, blue: {type: diffuse, albedo: [0.2, 0.3, 0.7]},\n"
      "            metal: {type: diffuse, albedo: [0.9, 0.7, 0.4]}}\n"
      "shapes:\n"
      "  - {type: rectangle, material: floor, transform: {scale: 5, rotate_x: -90}}\n"
      "  - {type: box, material: blue, transform: {scale: 0.4, rotate_y: 30, translate: [-0.8, 0.4, 0]}}\n"
      "  - {type: sphere, material: metal, center: [0.7, 0.5, 0.2], radius: 0.5}\n";
  const std::vector<std::pair<std::string, std::string>> lights = {
      {"directional", "lights: [{type: directional, direction: [-0.4, -1, -0.6], irradiance: 2.5}]\n"},
      {"spot", "lights: [{type: spot, position: [1, 3, 2], look_at: [0, 0, 0], intensity: 20, cone_angle: 25}]\n"},
      {"environment", "lights: [{type: environment, radiance: 0.8}]\n"}};
  for (const auto& [name, light] : lights) {
    SceneFile sf = loadSceneFromString(geometry + light, name + ".yaml");
    auto pt = renderScene(sf, {"path", "{max_depth: 6}", 512, 31});
    auto lt = renderScene(sf, {"light", "{max_depth: 6}", 512, 32});
    auto bd = renderScene(sf, {"bdpt", "{max_depth: 6}", 256, 33});
    std::vector<bool> mask = diffusePrimaryHits(*sf.scene);
    double alpha = Alpha / (2 * lights.size());
    EXPECT_EQ(compareRegions(regionMeans(*lt, 4, 4, &mask), regionMeans(*pt, 4, 4, &mask), alpha), "") << name << ": LT vs PT";
    EXPECT_EQ(compareRegions(regionMeans(*bd, 4, 4), regionMeans(*pt, 4, 4), alpha), "") << name << ": BDPT vs PT";
    EXPECT_EQ(lt->nonFiniteCount() + bd->nonFiniteCount(), 0u) << name;
  }
}

TEST(LightTracer, PointLightOverDiffusePlaneIsAnalytic) {
  SceneFile sf = loadSceneFromString(PointLightPlaneScene, "point-plane.yaml");
  auto film = renderScene(sf, {"light", "{max_depth: 2}", 256, 4});
  EXPECT_TRUE(meanMatches(*film, pointLightOverPlane(sf.scene->camera, Vec3(0.3f, 2, 0.2f), 10, 0.5f), Alpha));
}

TEST(LightTracer, AgreesWithPathTracingUnderShadingNormals) {
  // A smooth-shaded low-poly sphere: shading normals differ from geometric
  // ones by up to ~20°, so the adjoint correction (Veach §5.3) matters.
  std::string dir = ::testing::TempDir();
  {
    std::ofstream obj(dir + "/lowpoly.obj");
    const int rings = 4, segments = 8;
    obj << "v 0 1 0\n";
    for (int r = 1; r < rings; ++r)
      for (int s = 0; s < segments; ++s) {
        float th = Pi * r / rings, ph = 2 * Pi * s / segments;
        obj << "v " << std::sin(th) * std::cos(ph) << " " << std::cos(th) << " " << std::sin(th) * std::sin(ph) << "\n";
      }
    obj << "v 0 -1 0\n";
    int bottom = 2 + (rings - 1) * segments;
    for (int s = 0; s < segments; ++s) obj << "f 1 " << 2 + (s + 1) % segments << " " << 2 + s << "\n";
    for (int r = 0; r < rings - 2; ++r)
      for (int s = 0; s < segments; ++s) {
        int a = 2 + r * segments + s, b = 2 + r * segments + (s + 1) % segments;
        obj << "f " << a << " " << b << " " << b + segments << "\nf " << a << " " << b + segments << " " << a + segments << "\n";
      }
    for (int s = 0; s < segments; ++s) {
      int a = 2 + (rings - 2) * segments + s, b = 2 + (rings - 2) * segments + (s + 1) % segments;
      obj << "f " << a << " " << b << " " << bottom << "\n";
    }
  }
  std::string scene = "camera: {position: [0, 1.2, 3.5], look_at: [0, 0.6, 0], fov: 35}\n"
                      "film: {width: 32, height: 32}\n"
                      "materials: {m: {type: diffuse, albedo: 0.8}, floor: {type: diffuse, albedo: 0.5}}\n"
                      "shapes:\n"
                      "  - {type: rectangle, material: floor, transform: {scale: 4, rotate_x: -90}}\n"
                      "  - {type: mesh, file: lowpoly.obj, smooth_normals: true, material: m, transform: {scale: 0.7, translate: [0, 0.7, 0]}}\n"
                      "  - {type: rectangle, material: none, emission: 8, transform: {scale: 0.5, rotate_x: 90, translate: [0.5, 2.5, 1]}}\n";
  SceneFile sf = loadSceneFromString(scene, dir + "/shading-normals.yaml");
  auto pt = renderScene(sf, {"path", "{max_depth: 6}", 1024, 11});
  auto lt = renderScene(sf, {"light", "{max_depth: 6}", 1024, 12});
  EXPECT_EQ(compareRegions(regionMeans(*lt, 4, 4), regionMeans(*pt, 4, 4), Alpha), "");
}

TEST(Bdpt, UnweightedStrategiesAreUnbiasedWhereTheyApply) {
  // Direct light only (paths of exactly 2 segments): NEE (s=1,t=2) and light
  // tracing (s=2,t=1) can each sample all of them in the diffuse Cornell box;
  // each unweighted image must match PT(max_depth 2) − PT(max_depth 1).
  SceneFile sf = loadShippedScene("cornell-box", 24, 24);
  auto pt2 = renderScene(sf, {"path", "{max_depth: 2}", 1024, 21});
  auto pt1 = renderScene(sf, {"path", "{max_depth: 1}", 64, 22});
  RegionMeans a = regionMeans(*pt2, 3, 3), b = regionMeans(*pt1, 3, 3), direct = a;
  for (size_t i = 0; i < a.mean.size(); ++i)
    direct.mean[i] = a.mean[i] - b.mean[i], direct.varianceOfMean[i] = a.varianceOfMean[i] + b.varianceOfMean[i];

  BdptSettings s;
  s.length.maxDepth = 2;
  s.strategyImages = 2;
  Bdpt bdpt(s);
  Film film(24, 24);
  RenderOptions o;
  o.seed = 23;
  o.budget.spp = 1024;
  renderLoop(*sf.scene, bdpt, film, sf.sampler, o);
  for (auto [sCount, tCount] : {std::pair{1, 2}, std::pair{2, 1}}) {
    const Film* raw = bdpt.strategyFilm(sCount, tCount, false);
    ASSERT_NE(raw, nullptr);
    EXPECT_EQ(compareRegions(regionMeans(*raw, 3, 3), direct, Alpha / 2), "") << "s=" << sCount << " t=" << tCount;
  }
  // The weighted strategy images of length 2 add up to BDPT's length-2 part,
  // and BDPT's image is their sum over lengths 1 and 2: check the total.
  Image total(24, 24);
  for (auto [sCount, tCount] : {std::pair{0, 2}, std::pair{0, 3}, std::pair{1, 2}, std::pair{2, 1}}) {
    Image w = bdpt.strategyFilm(sCount, tCount, true)->image();
    for (size_t i = 0; i < total.pixels.size(); ++i) total.pixels[i] += w.pixels[i];
  }
  Image full = film.image();
  for (size_t i = 0; i < total.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c)  // the same contributions summed in another order: rounding only
      ASSERT_NEAR(total.pixels[i][c], full.pixels[i][c], 1e-5f * (1 + full.pixels[i][c]));
}

TEST(Bidirectional, SameSeedIsBitIdenticalWithOneAndTwoThreads) {
  SceneFile sf = loadShippedScene("cornell-box-spheres", 40, 40);
  for (std::string integrator : {"light", "bdpt", "photon"}) {
    std::string params = integrator == "photon" ? "{global_photons: 20000, caustic_photons: 20000}" : "{}";
    Image one = renderScene(sf, {integrator, params, 4, 42, 1})->image();
    Image two = renderScene(sf, {integrator, params, 4, 42, 2})->image();
    EXPECT_EQ(std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(Color)), 0) << integrator;
  }
}

}  // namespace
}  // namespace lb::test
