// MIS compensation of the environment map (core/lights/environment_map_light.h;
// Karlík, Šik, Vévoda, Skřivan & Křivánek 2019): the compensated density
// against one written from its definition with exact texel solid angles,
// its sampler against it (χ²), and the path tracer that uses it agreeing
// with the one that does not (it moves variance, never the mean).
#include <gtest/gtest.h>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <yaml-cpp/yaml.h>
#include <glm/gtc/matrix_transform.hpp>
#include <unistd.h>
#include "core/image.h"
#include "core/lights/environment_map_light.h"
#include "tests/support/render_helpers.h"
#include "tests/support/sky_maps.h"
#include "tests/support/statistics.h"

namespace lb::test {
namespace {

constexpr double Alpha = 0.01;
const Bounds3 SceneBounds{Vec3(-1.f), Vec3(1.f)};


// The density from the definition. A texel is chosen with probability
// P ∝ max(0, m − m̄) · ΔΩ, m = max(r, g, b) of the texel, m̄ = ∫ m dω / 4π,
// every integral summed with the texel's exact solid angle
// ΔΩ = 2π/w · Δcos θ (the code weighs rows by sin θ at their centres:
// proportional, so the same P); a point is then uniform in the texel's
// (u, v), whose density per steradian at θ is P · w h / (2π² sin θ).
// Directions are the map's (Mitsuba's convention), turned by `toWorld`.
struct DefinitionDensity {
  std::vector<double> probability;  // per texel
  int w, h;
  DefinitionDensity(const Image& map) : w(map.width), h(map.height) {
    auto m = [&](int x, int y) {
      const Color& c = map.at(x, y);
      return double(std::max({c.r, c.g, c.b}));
    };
    auto solidAngle = [&](int y) { return 2 * Pi / w * (std::cos(Pi * y / h) - std::cos(Pi * (y + 1) / h)); };
    double mean = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) mean += m(x, y) * solidAngle(y);
    mean /= 4 * Pi;
    double total = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) total += std::max(0.0, m(x, y) - mean) * solidAngle(y);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) probability.push_back(std::max(0.0, m(x, y) - mean) * solidAngle(y) / total);
  }
  // Per steradian at the centre of texel (x, y).
  double density(int x, int y) const {
    return probability[size_t(y * w + x)] * w * h / (2 * Pi * Pi * std::sin(Pi * (y + 0.5) / h));
  }
  // The world direction through the centre of texel (x, y).
  static Vec3 direction(int x, int y, int w, int h, const Mat3& toWorld) {
    double phi = 2 * Pi * (x + 0.5) / w, theta = Pi * (y + 0.5) / h;
    return toWorld * Vec3(float(std::sin(theta) * std::sin(phi)), float(std::cos(theta)),
                          float(-std::sin(theta) * std::cos(phi)));
  }
};

TEST(EnvironmentMapCompensation, DensityIsTheMapAboveItsMean) {
  const Image map = skyWithSun();
  const Mat3 toWorld = rotationAbout(35.f, Vec3(0.3f, 1, 0));  // the map's frame must be undone
  EnvironmentMapLight env(map, 2.f, toWorld, true);
  env.preprocess(SceneBounds);
  DefinitionDensity expected(map);
  int zero = 0, positive = 0;
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      double want = expected.density(x, y);
      Vec3 d = DefinitionDensity::direction(x, y, map.width, map.height, toWorld);
      double got = env.pdfLiCompensated(Vec3(0.f), d, {}, {});
      if (want == 0) {
        EXPECT_EQ(got, 0.0) << "texel " << x << ", " << y << " is below the mean";
        ++zero;
      } else {
        // float weights and pmfs: a few ulp each.
        EXPECT_NEAR(got, want, 1e-4 * want) << "texel " << x << ", " << y;
        ++positive;
      }
    }
  // Both kinds of texel were seen: the case where compensation matters.
  EXPECT_GT(zero, map.width * map.height / 2);
  EXPECT_GT(positive, 20);
  // The uncompensated density is untouched (and positive where this one is 0).
  Vec3 dark = DefinitionDensity::direction(60, 30, map.width, map.height, toWorld);
  EXPECT_GT(env.pdfLi(Vec3(0.f), dark, {}, {}), 0.f);
}

TEST(EnvironmentMapCompensation, SamplerMatchesItsDensity) {
  EnvironmentMapLight env(skyWithSun(), 1.f, rotationAbout(-20.f, Vec3(1, 0, 0.5f)), true);
  env.preprocess(SceneBounds);
  SphereHistogramTest t;
  auto r = t.run(
      [&](Vec2 u, float) -> std::optional<Vec3> {
        auto s = env.sampleLiCompensated(Vec3(0.f), 0, u);
        if (!s) return std::nullopt;
        return s->wi;
      },
      [&](const Vec3& w) { return double(env.pdfLiCompensated(Vec3(0.f), w, {}, {})); }, 71);
  EXPECT_TRUE(r.passed(Alpha)) << r.message << " p=" << r.pValue;
}

TEST(EnvironmentMapCompensation, AConstantMapKeepsItsFullDensity) {
  // No texel is above the mean: the compensated density would be zero
  // everywhere, so the map keeps its own.
  Image grey(16, 8);
  for (Color& p : grey.pixels) p = Color(0.7f);
  EnvironmentMapLight env(grey, 1.f, Mat3(1.f), true);
  env.preprocess(SceneBounds);
  for (Vec3 d : {Vec3(0, 1, 0.2f), Vec3(1, 0, 0), Vec3(-0.3f, -0.8f, 0.5f)}) {
    d = glm::normalize(d);
    EXPECT_GT(env.pdfLiCompensated(Vec3(0.f), d, {}, {}), 0.f);
    EXPECT_EQ(env.pdfLiCompensated(Vec3(0.f), d, {}, {}), env.pdfLi(Vec3(0.f), d, {}, {}));
  }
}

// A diffuse sphere on a diffuse floor under the sunny sky.
std::string diffuseScene(const std::string& mapPath) {
  return "camera: {position: [0, 1.2, 4], look_at: [0, 0.4, 0], fov: 35}\n"
         "film: {width: 24, height: 16}\n"
         "materials:\n"
         "  white: {type: diffuse, albedo: 0.7}\n"
         "  metal: {type: conductor, roughness: 0.2, eta: [0.2, 0.92, 1.1], k: [3.9, 2.45, 2.14]}\n"
         "shapes:\n"
         "  - {type: sphere, center: [-0.5, 0.4, 0], radius: 0.4, material: white}\n"
         "  - {type: sphere, center: [0.5, 0.4, 0], radius: 0.4, material: metal}\n"
         "  - {type: rectangle, material: white, transform: {scale: 3, rotate_x: -90}}\n"
         "lights:\n  - {type: environment, file: " + mapPath + ", rotate_y: 40}\n";
}

// Compensation changes which strategy carries which directions, not the
// image: per-region z-tests against the uncompensated path tracer.
TEST(EnvironmentMapCompensation, PathTracingAgreesWithAndWithoutIt) {
  std::string path = (std::filesystem::temp_directory_path() /
                      ("lightbench-sunny-" + std::to_string(getpid()) + ".exr")).string();
  writeExr(path, skyWithSun());
  SceneFile scene = loadSceneFromString(diffuseScene(path), "/tmp/scene.yaml");
  std::filesystem::remove(path);
  auto plain = renderScene(scene, {"path", "{max_depth: 4}", 1024, 72});
  // Every way the path estimator counts its light samples and directions:
  // three heuristics, two shadow rays, branching at the first vertex, the
  // spatial light choice, the wavefront engine, and the guided mixture.
  const std::pair<const char*, const char*> cases[] = {
      {"path", "{mis: power}"},
      {"path", "{mis: balance}"},
      {"path", "{mis: one_sample}"},
      {"path", "{shadow_rays: 2, first_bounce_samples: 2}"},
      {"path", "{light_selection: spatial}"},
      {"path", "{engine: wavefront}"},
      {"guided", "{}"},
  };
  const double level = Alpha / std::size(cases);
  for (const auto& [integrator, keys] : cases) {
    YAML::Node params = YAML::Load(keys);
    params["max_depth"] = 4;
    params["mis_compensation"] = true;
    YAML::Emitter out;
    out << YAML::Flow << params;
    auto compensated = renderScene(scene, {integrator, out.c_str(), 1024, 73});
    std::string failures = compareRegions(regionMeans(*plain, 4, 4), regionMeans(*compensated, 4, 4), level);
    EXPECT_TRUE(failures.empty()) << integrator << " " << out.c_str() << "\n" << failures;
  }
}

}  // namespace
}  // namespace lb::test
