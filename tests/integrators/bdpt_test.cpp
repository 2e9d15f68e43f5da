// BDPT bookkeeping (testing.md §4): MIS weights of all strategies sum to 1 on
// random paths (delta BSDFs, delta lights, both heuristics and uniform), and
// cached subpath densities equal a fresh recomputation.
#include <gtest/gtest.h>
#include "core/sampler.h"
#include "integrators/bdpt/bdpt.h"
#include "integrators/bidirectional/subpaths.h"
#include "integrators/bidirectional/verification.h"
#include "tests/support/render_helpers.h"

namespace lb::test {
namespace {

using bidir::MisWeighting;

using bidir::Vertex;

BdptSettings settings(int maxDepth) {
  BdptSettings s;
  s.length.maxDepth = maxDepth;
  s.length.russianRoulette = false;
  return s;
}

// Weights are products and sums of at most 2n float ratios, each rounded
// once: their sum is 1 up to about 4n ulp of float; 16n leaves headroom.
double sumTolerance(size_t n) { return 16.0 * double(n) * std::numeric_limits<float>::epsilon(); }

// Returns false (checking nothing) for a path no strategy can sample, e.g.
// camera → glass → glass → directional light (L S S E with a delta light):
// such paths carry no contribution in any renderer.
bool expectWeightsSumToOne(const Scene& scene, const std::vector<Vertex>& path, const char* what) {
  // A path that reaches an emitter's unlit side carries nothing, and emission
  // sampling cannot produce it: the strategies that could are not defined.
  const Vertex& end = path.back();
  if (end.type == bidir::VertexType::Surface && isBlack(bidir::emitted(scene, end, path[path.size() - 2]))) return false;
  for (MisWeighting h : {MisWeighting::Balance, MisWeighting::Power, MisWeighting::Uniform}) {
    auto w = bidir::strategyWeights(scene, h, path);
    double sum = 0;
    int possible = 0;
    for (float x : w)
      if (x >= 0) sum += x, ++possible;
    if (possible == 0) return false;
    EXPECT_NEAR(sum, 1.0, sumTolerance(path.size())) << what << ", length " << path.size() - 1 << ", heuristic "
                                                     << int(h);
  }
  return true;
}

TEST(Bdpt, MisWeightsSumToOneOnPathsEndingOnAreaLights) {
  // Cornell box with mirror and glass spheres: random camera subpaths, cut at
  // their first emitter hit, through delta and diffuse vertices.
  SceneFile sf = loadShippedScene("cornell-box-spheres", 32, 32);
  const Scene& scene = *sf.scene;
  IndependentSampler sampler(5);
  std::vector<Vertex> camera(12);
  uint64_t rays = 0;
  int checked = 0, withDelta = 0;
  for (uint64_t i = 0; checked < 300 && i < 200000; ++i) {
    sampler.start(i, 0);
    int n = bidir::generateCameraSubpath(scene, sampler, settings(10).length, Vec2(sampler.get1D() * 32, sampler.get1D() * 32),
                                        camera, rays);
    for (int k = 1; k < n; ++k)
      if (camera[size_t(k)].isLight()) {
        std::vector<Vertex> path(camera.begin(), camera.begin() + k + 1);
        bool delta = false;
        for (const auto& v : path) delta |= v.delta;
        withDelta += delta;
        checked += expectWeightsSumToOne(scene, path, "area light");
        break;
      }
  }
  EXPECT_EQ(checked, 300);
  EXPECT_GT(withDelta, 10);  // the sample really includes specular chains
}

TEST(Bdpt, MisWeightsSumToOneOnPathsFromAPointLight) {
  // Light subpaths from a point light (a delta light: s = 0 cannot sample
  // them), joined to the camera where their last vertex is in view.
  SceneFile sf = loadShippedScene("point-light", 32, 24);
  const Scene& scene = *sf.scene;
  IndependentSampler sampler(6);
  std::vector<Vertex> light(10);
  uint64_t rays = 0;
  int checked = 0;
  for (uint64_t i = 0; checked < 300 && i < 200000; ++i) {
    sampler.start(i, 0);
    int n = bidir::generateLightSubpath(scene, sampler, settings(10).length, light, rays);
    if (n < 2) continue;
    int last = 1 + int(sampler.get1D() * float(n - 1));  // a random prefix y0 … y(last)
    if (!scene.camera.connect(light[size_t(last)].p)) continue;
    std::vector<Vertex> path = {bidir::cameraVertex(scene.camera, Color(1.f))};
    for (int k = last; k >= 0; --k) path.push_back(light[size_t(k)]);
    checked += expectWeightsSumToOne(scene, path, "point light");
  }
  EXPECT_EQ(checked, 300);
}

// The cached density used the sampled direction, leaving the ray's offset
// origin; the recomputation uses the direction between the stored vertices.
// They differ by an angle of about the offset over the segment length,
// ε = γ(7)(|a| + |b|)/d (the error bound the offsets come from), which a
// cosine-shaped density turns into a relative error of ε(1 + tanθ) at the
// sampling vertex, and the area conversion's |cos θ_b| into ε·tanθ_b at the
// receiving one (and, at a specular vertex, the incoming segment's error
// moves its Fresnel probability). The bound: relative 1e-3 (glossy lobes' slope times float
// rounding) plus 64 times that conditioning term.
float tolerance(const std::vector<Vertex>& path, const bidir::PdfMismatch& m) {
  int from = m.reverse ? m.vertex + 1 : m.vertex - 1;  // where the direction was sampled
  const Vertex &a = path[size_t(from)], &b = path[size_t(m.vertex)];
  float d = glm::length(b.p - a.p);
  // The offset is |n|₁ ≤ √3 times the error bound, which for triangles is
  // widened to its largest component in every direction (core/shape.cpp).
  float eps = std::sqrt(3.f) * gamma(7) * (maxComponent(glm::abs(a.p)) + maxComponent(glm::abs(b.p))) / std::max(d, 1e-30f);
  auto tanAt = [&](float cos) { return std::sqrt(std::max(0.f, 1 - cos * cos)) / std::max(cos, 1e-6f); };
  float tanA = a.type == bidir::VertexType::Surface ? tanAt(absDot(a.shadingNormal(), (b.p - a.p) / d)) : 0.f;
  float tanB = b.onSurface() ? tanAt(absDot(b.ng, (b.p - a.p) / d)) : 0.f;
  float bound = 1e-3f + 64 * eps * (1 + tanA + tanB);
  // A specular vertex's density is its Fresnel lobe probability, a function
  // of the incoming direction: that segment's offset error counts too.
  int before = m.reverse ? from + 1 : from - 1;
  if (a.delta && before >= 0 && before < int(path.size())) {
    const Vertex& p = path[size_t(before)];
    float dIn = glm::length(a.p - p.p);
    float epsIn = std::sqrt(3.f) * gamma(7) * (maxComponent(glm::abs(a.p)) + maxComponent(glm::abs(p.p))) / std::max(dIn, 1e-30f);
    bound += 64 * epsIn * (1 + tanAt(absDot(a.ng, (p.p - a.p) / dIn)));
  }
  return bound;
}

TEST(Bdpt, MisWeightsSumToOneUnderDirectionalAndEnvironmentLights) {
  const std::string geometry =
      "camera: {position: [0, 2, 5], look_at: [0, 0.4, 0], fov: 40}\n"
      "film: {width: 32, height: 24}\n"
      "materials: {floor: {type: diffuse, albedo: 0.6}, glass: {type: dielectric, ior: 1.5},\n"
      "            metal: {type: conductor, roughness: 0.3}}\n"
      "shapes:\n"
      "  - {type: rectangle, material: floor, transform: {scale: 5, rotate_x: -90}}\n"
      "  - {type: sphere, material: glass, center: [-0.7, 0.5, 0], radius: 0.5}\n"
      "  - {type: sphere, material: metal, center: [0.7, 0.5, 0.2], radius: 0.5}\n";
  // Environment: camera subpaths that escape (their last vertex is the environment).
  {
    SceneFile sf = loadSceneFromString(geometry + "lights: [{type: environment, radiance: 1}]\n", "env.yaml");
    IndependentSampler sampler(12);
    std::vector<Vertex> camera(12);
    uint64_t rays = 0;
    int checked = 0;
    for (uint64_t i = 0; checked < 200 && i < 100000; ++i) {
      sampler.start(i, 0);
      int n = bidir::generateCameraSubpath(*sf.scene, sampler, settings(10).length, Vec2(sampler.get1D() * 32, sampler.get1D() * 24),
                                          camera, rays);
      if (n < 3 || !camera[size_t(n - 1)].isInfiniteLight()) continue;  // at least one bounce before escaping
      checked += expectWeightsSumToOne(*sf.scene, std::vector<Vertex>(camera.begin(), camera.begin() + n), "environment");
    }
    EXPECT_EQ(checked, 200);
  }
  // Directional (a delta light at infinity): light subpaths joined to the camera.
  {
    SceneFile sf = loadSceneFromString(geometry + "lights: [{type: directional, direction: [-0.4, -1, -0.6]}]\n", "dir.yaml");
    IndependentSampler sampler(13);
    std::vector<Vertex> light(10);
    uint64_t rays = 0;
    int checked = 0;
    for (uint64_t i = 0; checked < 200 && i < 200000; ++i) {
      sampler.start(i, 0);
      int n = bidir::generateLightSubpath(*sf.scene, sampler, settings(10).length, light, rays);
      if (n < 2) continue;
      int last = 1 + int(sampler.get1D() * float(n - 1));
      if (!sf.scene->camera.connect(light[size_t(last)].p)) continue;
      std::vector<Vertex> path = {bidir::cameraVertex(sf.scene->camera, Color(1.f))};
      for (int k = last; k >= 0; --k) path.push_back(light[size_t(k)]);
      checked += expectWeightsSumToOne(*sf.scene, path, "directional");
    }
    EXPECT_EQ(checked, 200);
  }
}

TEST(Bdpt, CachedDensitiesEqualRecomputation) {
  // The random walks' pdfFwd/pdfRev against the same densities recomputed
  // from the BSDFs, lights and camera at the stored vertices.
  for (std::string name : {"cornell-box-spheres", "veach-mis"}) {
    SceneFile sf = loadShippedScene(name, 32, 32);
    IndependentSampler sampler(9);
    std::vector<Vertex> path(12);
    uint64_t rays = 0;
    int compared = 0;
    for (uint64_t i = 0; i < 2000; ++i) {
      for (bool lightPath : {false, true}) {
        sampler.start(i, lightPath);
        int n = lightPath ? bidir::generateLightSubpath(*sf.scene, sampler, settings(10).length, path, rays)
                          : bidir::generateCameraSubpath(*sf.scene, sampler, settings(10).length,
                                                        Vec2(sampler.get1D() * 32, sampler.get1D() * 32), path, rays);
        for (const auto& m : bidir::checkSubpathPdfs(*sf.scene, path, n, lightPath)) {
          ++compared;
          ASSERT_NEAR(m.cached, m.recomputed, tolerance(path, m) * std::max(m.cached, m.recomputed) + 1e-30f)
              << name << (lightPath ? " light" : " camera") << " subpath, vertex " << m.vertex
              << (m.reverse ? " pdfRev" : " pdfFwd");
        }
      }
    }
    EXPECT_GT(compared, 2000) << name;
  }
}

}  // namespace
}  // namespace lb::test
