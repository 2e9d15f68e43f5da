// Light sampling tests: χ² of sampleLi against pdfLi (directions seen from a
// reference point) and of sampleLe's directions against pdfLe; emitted power
// against an independent Monte Carlo estimate.
#include <gtest/gtest.h>
#include "core/lights/area_light.h"
#include "core/lights/environment_light.h"
#include "core/lights/point_light.h"
#include "core/lights/spot_light.h"
#include "core/rng.h"
#include "core/shape.h"
#include "tests/support/statistics.h"

namespace lb::test {
namespace {

constexpr double Alpha = 0.01;

Shape rectangle(float halfW, float halfH, Vec3 center) {
  TriangleMesh m;
  m.positions = {center + Vec3(-halfW, -halfH, 0), center + Vec3(halfW, -halfH, 0), center + Vec3(halfW, halfH, 0),
                 center + Vec3(-halfW, halfH, 0)};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return Shape::mesh(m);
}

// Directions from `ref` to the light, and the pdf found by tracing each
// direction back onto the shape (so pdfLi is checked with its own arguments).
Chi2Result testLi(const Light& light, const Shape& shape, const Vec3& ref, uint64_t seed) {
  SphereHistogramTest t;
  t.samples = 300000;
  // Zoom on the cap around the light's bounding sphere, as seen from ref.
  Bounds3 b = shape.bounds();
  Vec3 toCenter = b.center() - ref;
  float dist = glm::length(toCenter), radius = b.radius();
  if (dist > radius * 1.01f) {
    t.frame = Frame(toCenter / dist);
    t.zMin = std::cos(std::min(float(M_PI), 1.2f * std::asin(std::min(1.f, radius / dist))));
  }
  Pcg32 pick(seed, 99);
  return t.run(
      [&](Vec2 u, float) -> std::optional<Vec3> {
        auto s = light.sampleLi(ref, pick.next1D(), u);
        if (!s) return std::nullopt;
        return s->wi;
      },
      [&](const Vec3& wi) -> double {
        // Closest hit of the ray (ref, wi) with the shape, by brute force.
        // In double precision, so edge-on silhouettes are judged correctly.
        glm::dvec3 o(ref), d(wi);
        if (shape.isSphere()) {
          const Sphere& sp = shape.sphereData();
          glm::dvec3 oc = o - glm::dvec3(sp.center);
          double b = glm::dot(oc, d), c = glm::dot(oc, oc) - double(sp.radius) * sp.radius, disc = b * b - c;
          if (disc < 0) return 0;
          double t0 = -b - std::sqrt(disc), t1 = -b + std::sqrt(disc);
          double th = t0 > 0 ? t0 : t1;
          if (th <= 0) return 0;
          Vec3 p(o + th * d), n(glm::normalize(o + th * d - glm::dvec3(sp.center)));
          if (sp.flipNormals) n = -n;
          if (isBlack(light.L(n, -wi))) return 0;
          return light.pdfLi(ref, wi, p, n);
        }
        const TriangleMesh& m = shape.triangleMesh();
        for (const auto& tri : m.triangles) {
          glm::dvec3 a(m.positions[tri.x]), e1 = glm::dvec3(m.positions[tri.y]) - a,
              e2 = glm::dvec3(m.positions[tri.z]) - a;
          glm::dvec3 n = glm::normalize(glm::cross(e1, e2));
          double denom = glm::dot(n, d);
          if (denom == 0) continue;
          double th = glm::dot(n, a - o) / denom;
          if (th <= 0) continue;
          glm::dvec3 p = o + th * d, q = p - a;
          double d00 = glm::dot(e1, e1), d01 = glm::dot(e1, e2), d11 = glm::dot(e2, e2);
          double d20 = glm::dot(q, e1), d21 = glm::dot(q, e2), den = d00 * d11 - d01 * d01;
          double v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
          if (v < 0 || w < 0 || v + w > 1) continue;
          if (isBlack(light.L(Vec3(n), -wi))) return 0;
          return light.pdfLi(ref, wi, Vec3(p), Vec3(n));
        }
        return 0;
      },
      seed);
}

TEST(Lights, AreaLightSampleLiMatchesPdfLi) {
  const int tests = 6;
  Shape rect = rectangle(0.5f, 0.3f, Vec3(0.2f, 0.1f, 1.f));
  AreaLight oneSided(&rect, Color(1.f), false), twoSided(&rect, Color(1.f), true);
  Shape ball = Shape::sphere({Vec3(0.3f, -0.2f, 2.f), 0.7f, false});
  AreaLight sphere(&ball, Color(1.f), false);
  Shape room = Shape::sphere({Vec3(0.f), 3.f, true});
  AreaLight enclosing(&room, Color(1.f), false);
  struct C { const char* name; const Light* light; const Shape* shape; Vec3 ref; };
  std::vector<C> cases = {{"rectangle, facing", &oneSided, &rect, Vec3(0, 0, 2.5f)},
                          {"rectangle, two-sided from behind", &twoSided, &rect, Vec3(-0.3f, 0.2f, 0.2f)},
                          {"rectangle, oblique (14 deg elevation)", &twoSided, &rect, Vec3(2.f, 0.f, 1.5f)},
                          {"sphere, outside (cone sampling)", &sphere, &ball, Vec3(0.f)},
                          {"sphere, far (small-angle branch)", &sphere, &ball, Vec3(0.f, 0.f, -60.f)},
                          {"inside an inward-facing sphere", &enclosing, &room, Vec3(0.5f, 0.2f, -1.f)}};
  uint64_t seed = 10;
  for (const auto& c : cases) {
    auto r = testLi(*c.light, *c.shape, c.ref, seed++);
    EXPECT_TRUE(r.passed(Alpha / tests)) << c.name << ": " << r.message << " p=" << r.pValue;
  }
}

TEST(Lights, EnvironmentSampleLiMatchesPdfLi) {
  EnvironmentLight env(Color(1.f));
  env.preprocess(Bounds3{Vec3(-1.f), Vec3(1.f)});
  SphereHistogramTest t;
  auto r = t.run([&](Vec2 u, float) { return std::optional<Vec3>(env.sampleLi(Vec3(0.f), 0, u)->wi); },
                 [&](const Vec3& w) { return double(env.pdfLi(Vec3(0.f), w, {}, {})); }, 21);
  EXPECT_TRUE(r.passed(Alpha)) << r.message << " p=" << r.pValue;
}

TEST(Lights, EmittedDirectionsMatchPdfLe) {
  Shape rect = rectangle(0.5f, 0.3f, Vec3(0.f));
  AreaLight oneSided(&rect, Color(1.f), false), twoSided(&rect, Color(1.f), true);
  PointLight point(Vec3(0.f), Color(1.f));
  SpotLight spot(Vec3(0.f), Vec3(0.2f, 0.3f, 1.f), Color(1.f), 35, 20);
  std::vector<std::pair<const char*, const Light*>> lights = {
      {"area", &oneSided}, {"area two-sided", &twoSided}, {"point", &point}, {"spot", &spot}};
  uint64_t seed = 30;
  for (auto& [name, light] : lights) {
    SphereHistogramTest t;
    t.samples = 300000;
    Pcg32 extra(seed, 5);
    auto r = t.run(
        [&](Vec2 u, float uPick) -> std::optional<Vec3> {
          auto e = light->sampleLe(uPick, extra.next2D(), u);
          if (!e || e->pdfDir == 0) return std::nullopt;
          return e->ray.d;
        },
        [&](const Vec3& d) {
          float pdfPos, pdfDir;
          light->pdfLe(Vec3(0.f), Vec3(0, 0, 1), d, &pdfPos, &pdfDir);
          return double(pdfDir);
        },
        seed++);
    EXPECT_TRUE(r.passed(Alpha / lights.size())) << name << ": " << r.message << " p=" << r.pValue;
  }
}

TEST(Lights, PowerMatchesMonteCarloOfEmission) {
  // Φ = ∫∫ Le cos dω dA, estimated from sampleLe: E[Le·|cos| / (pdfPos pdfDir)].
  Shape rect = rectangle(0.5f, 0.3f, Vec3(0.f));
  AreaLight area(&rect, Color(2.f), true);
  SpotLight spot(Vec3(0.f), Vec3(0, 0, 1), Color(3.f), 40, 25);
  std::vector<std::pair<const char*, const Light*>> lights = {{"area", &area}, {"spot", &spot}};
  double critical = normalCritical(0.01 / lights.size());
  for (auto& [name, light] : lights) {
    Pcg32 rng(77, 1);
    RunningStats phi;
    for (int i = 0; i < 200000; ++i) {
      auto e = light->sampleLe(rng.next1D(), rng.next2D(), rng.next2D());
      if (!e) {
        phi.add(0);
        continue;
      }
      float cos = glm::length(e->n) > 0 ? absDot(e->n, e->ray.d) : 1.f;
      phi.add(double(e->Le.r) * cos / (double(e->pdfPos) * e->pdfDir));
    }
    // For the cosine-sampled area light every term equals Φ up to float
    // rounding (zero variance), so allow the rounding of the float terms too.
    double rounding = 1e-6 * light->power().r;
    EXPECT_LE(std::abs(phi.mean - light->power().r), critical * std::sqrt(phi.varianceOfMean()) + rounding) << name;
  }
}

}  // namespace
}  // namespace lb::test
