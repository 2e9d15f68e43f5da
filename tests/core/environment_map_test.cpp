// The HDR environment map (core/lights/environment_map_light.h): χ² tests of
// both sampling routines against their pdfs, the estimator's mean against an
// independent texel-by-texel integral, a constant map against the constant
// environment, and unbiased integrators agreeing on a glossy object it lights.
#include <gtest/gtest.h>
#include <cmath>
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>
#include <unistd.h>
#include "core/image.h"
#include "core/lights/environment_map_light.h"
#include "core/rng.h"
#include "tests/support/render_helpers.h"
#include "tests/support/sky_maps.h"
#include "tests/support/statistics.h"

namespace lb::test {
namespace {

constexpr double Alpha = 0.01;
const Bounds3 SceneBounds{Vec3(-1.f), Vec3(1.f)};


TEST(EnvironmentMap, SampleLiMatchesPdfLi) {
  for (bool importance : {true, false}) {
    EnvironmentMapLight env(skyWithSun(), 1.f, rotationAbout(30.f, Vec3(0, 1, 0)), importance);
    env.preprocess(SceneBounds);
    SphereHistogramTest t;
    auto r = t.run(
        [&](Vec2 u, float) -> std::optional<Vec3> {
          auto s = env.sampleLi(Vec3(0.f), 0, u);
          if (!s) return std::nullopt;
          return s->wi;
        },
        [&](const Vec3& w) { return double(env.pdfLi(Vec3(0.f), w, {}, {})); }, importance ? 61 : 62);
    EXPECT_TRUE(r.passed(Alpha / 4)) << (importance ? "importance" : "uniform") << ": " << r.message << " p=" << r.pValue;
  }
}

TEST(EnvironmentMap, EmittedDirectionsMatchPdfLe) {
  EnvironmentMapLight env(skyWithSun(), 1.f, rotationAbout(-50.f, Vec3(1, 1, 0.3f)), true);  // a general to_world
  env.preprocess(SceneBounds);
  Pcg32 positions(63, 1);
  SphereHistogramTest t;
  auto r = t.run(
      [&](Vec2 u, float) -> std::optional<Vec3> {
        auto e = env.sampleLe(0.5f, positions.next2D(), u);
        if (!e) return std::nullopt;
        return e->ray.d;
      },
      [&](const Vec3& d) {
        float pdfPos, pdfDir;
        env.pdfLe(Vec3(0.f), Vec3(0.f), d, &pdfPos, &pdfDir);
        return double(pdfDir);
      },
      64);
  EXPECT_TRUE(r.passed(Alpha)) << r.message << " p=" << r.pValue;
}

// E[Le(ω)/p(ω)] over sampleLi is ∫ Le dω, which integral() sums texel by
// texel from the solid angle of each texel row (2π/w · Δcos θ): independent
// of the sampler, its Jacobian and its pdf. z-test with the sample variance.
TEST(EnvironmentMap, EstimatorMeanIsTheIntegralOfTheMap) {
  for (bool importance : {true, false}) {
    EnvironmentMapLight env(skyWithSun(), 2.f, rotationAbout(10.f, Vec3(0, 1, 0)), importance);
    env.preprocess(SceneBounds);
    const Color exact = env.integral();
    Pcg32 rng(65, importance ? 1 : 2);
    const int n = 400000;
    for (int c = 0; c < 3; ++c) {
      double sum = 0, sum2 = 0;
      Pcg32 local = rng;
      for (int i = 0; i < n; ++i) {
        auto s = env.sampleLi(Vec3(0.f), 0, local.next2D());
        double f = s ? double(s->L[c]) / s->pdf : 0;
        sum += f, sum2 += f * f;
      }
      double mean = sum / n, var = (sum2 / n - mean * mean) / (n - 1);
      double z = (mean - exact[c]) / std::sqrt(var);
      EXPECT_LT(std::abs(z), normalCritical(Alpha / 6)) << "channel " << c << (importance ? " importance" : " uniform")
                                                          << ": " << mean << " vs " << exact[c];
    }
  }
  // A uniform map's integral is 4π times its value (the sphere's solid angle).
  Image grey(8, 4);
  for (Color& p : grey.pixels) p = Color(0.5f);
  EXPECT_NEAR(EnvironmentMapLight(grey, 1.f, Mat3(1.f), true).integral().g, 0.5 * 4 * Pi, 1e-5);
}

std::string writeMap(const Image& map, const std::string& name) {
  std::string path = (std::filesystem::temp_directory_path() / (name + "-" + std::to_string(getpid()) + ".exr")).string();
  writeExr(path, map);
  return path;
}

// A glossy sphere on a diffuse floor, lit by `light` (a YAML light mapping).
std::string glossyScene(const std::string& light) {
  return "camera: {position: [0, 1.2, 4], look_at: [0, 0.4, 0], fov: 35}\n"
         "film: {width: 24, height: 16}\n"
         "materials:\n"
         "  metal: {type: conductor, roughness: 0.15, eta: [0.2, 0.92, 1.1], k: [3.9, 2.45, 2.14]}\n"
         "  floor: {type: diffuse, albedo: 0.6}\n"
         "shapes:\n"
         "  - {type: sphere, center: [0, 0.5, 0], radius: 0.5, material: metal}\n"
         "  - {type: rectangle, material: floor, transform: {scale: 3, rotate_x: -90}}\n"
         "lights:\n  - " + light + "\n";
}

// A constant map is the constant environment: the same image in
// expectation (per-region z-tests), through the map's own sampler.
TEST(EnvironmentMap, AConstantMapRendersAsTheConstantEnvironment) {
  Image grey(16, 8);
  for (Color& p : grey.pixels) p = Color(1.5f);
  std::string path = writeMap(grey, "lightbench-constant-map");
  SceneFile map = loadSceneFromString(glossyScene("{type: environment, file: " + path + "}"), "/tmp/scene.yaml");
  SceneFile constant = loadSceneFromString(glossyScene("{type: environment, radiance: 1.5}"), "/tmp/scene.yaml");
  std::filesystem::remove(path);
  RenderSpec spec;
  spec.spp = 512;
  spec.seed = 66;
  std::string failures = compareScenes(map, constant, spec);
  EXPECT_TRUE(failures.empty()) << failures;
}

// Path tracing (NEE + MIS with the map's sampler) and BDPT (which also
// emits from the map) agree on a glossy sphere lit by a sky with a sun; so
// does light tracing where the camera first sees the diffuse floor.
TEST(EnvironmentMap, PathBdptAndLightTracingAgreeOnAGlossyObject) {
  std::string path = writeMap(skyWithSun(), "lightbench-sky-map");
  SceneFile scene = loadSceneFromString(glossyScene("{type: environment, file: " + path + ", rotate_y: 40}"),
                                        "/tmp/scene.yaml");
  std::filesystem::remove(path);
  RenderSpec spec;
  spec.params = "{max_depth: 6}";
  spec.spp = 1024;
  spec.seed = 68;
  auto pt = renderScene(scene, spec);
  spec.integrator = "bdpt";
  spec.spp = 256;
  spec.seed = 69;
  auto bdpt = renderScene(scene, spec);
  std::string failures = compareRegions(regionMeans(*pt, 4, 4), regionMeans(*bdpt, 4, 4), 1e-3);
  EXPECT_TRUE(failures.empty()) << "path vs bdpt:\n" << failures;

  std::vector<bool> floor = diffusePrimaryHits(*scene.scene);
  ASSERT_GT(countTrue(floor), 100u);
  spec.integrator = "light";
  spec.spp = 2048;
  spec.seed = 70;
  auto lt = renderScene(scene, spec);
  failures = compareRegions(regionMeans(*pt, 2, 2, &floor), regionMeans(*lt, 2, 2, &floor), 1e-3);
  EXPECT_TRUE(failures.empty()) << "path vs light tracing on the floor:\n" << failures;
}

}  // namespace
}  // namespace lb::test

namespace lb::test {
namespace {

// The map's orientation, pinned to Mitsuba's envmap (direction d in the map's
// frame ↦ u = atan2(d.x, −d.z)/2π, v = acos(d.y)/π, row 0 at the top) and to
// to_world turning the map's frame into the world's: one lit texel, looked
// for where the formula puts it and not where the inverse rotation would.
TEST(EnvironmentMap, OneLitTexelShinesFromWhereMitsubaPutsIt) {
  const int w = 16, h = 8, tx = 4, ty = 2;  // u = 0.28125, v = 0.3125
  Image map(w, h);
  map.at(tx, ty) = Color(1.f);
  const double u = (tx + 0.5) / w, v = (ty + 0.5) / h, phi = 2 * Pi * u, theta = Pi * v;
  // Inverting u = atan2(x, −z)/2π, v = acos(y)/π by hand.
  const Vec3 dMap(float(std::sin(theta) * std::sin(phi)), float(std::cos(theta)), float(-std::sin(theta) * std::cos(phi)));
  EnvironmentMapLight unrotated(map, 1.f, Mat3(1.f), true);
  EXPECT_EQ(unrotated.Le(dMap).r, 1.f);
  EXPECT_EQ(unrotated.Le(Vec3(dMap.x, dMap.y, -dMap.z)).r, 0.f);  // mirrored front to back: another texel
  const Mat3 r = rotationAbout(90.f, Vec3(0, 1, 0));
  EnvironmentMapLight turned(map, 1.f, r, true);
  EXPECT_EQ(turned.Le(r * dMap).r, 1.f);
  EXPECT_EQ(turned.Le(glm::transpose(r) * dMap).r, 0.f);
}

}  // namespace
}  // namespace lb::test
