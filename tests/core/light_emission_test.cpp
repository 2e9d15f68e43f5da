// Emission sampling (sampleLe) against pdfLe for every light type (issue 11):
// χ² of the emitted positions against pdfLe's position density, and of the
// emitted directions against pdfLe's direction density (for area lights
// conditionally on a fixed position, where the density depends on it); the
// pdfs sampleLe reports equal pdfLe's for the ray it returns; and triangle
// selection by area on a mesh with unequal triangles. Directions of the
// rectangle, point and spot lights are in lights_test.cpp.
#include <gtest/gtest.h>
#include "core/lights/area_light.h"
#include "core/lights/directional_light.h"
#include "core/lights/environment_light.h"
#include "core/lights/point_light.h"
#include "core/lights/spot_light.h"
#include "core/rng.h"
#include "core/shape.h"
#include "tests/support/statistics.h"

namespace lb::test {
namespace {

constexpr double Alpha = 0.01;
constexpr int Tests = 9;  // Bonferroni count for this file's χ² tests

// The rectangle [-0.5, 0.5] × [-0.3, 0.3] in z = 0 as a fan of five
// triangles around (0.4, -0.25) with areas 0.025, 0.03, 0.1375, 0.1375 and
// 0.27 (a factor 11 apart): uniform by area over the fan is uniform over the
// rectangle only if each triangle is picked in proportion to its area.
const Vec2 FanCentre(0.4f, -0.25f);
const std::vector<Vec2> FanRim = {{-0.5f, -0.3f}, {0.5f, -0.3f}, {0.5f, 0.3f}, {0.f, 0.3f}, {-0.5f, 0.3f}};

Shape fan() {
  TriangleMesh m;
  m.positions.push_back(Vec3(FanCentre, 0.f));
  for (Vec2 p : FanRim) m.positions.push_back(Vec3(p, 0.f));
  for (unsigned i = 0; i < FanRim.size(); ++i) m.triangles.push_back({0u, 1 + i, 1 + (i + 1) % unsigned(FanRim.size())});
  return Shape::mesh(m);
}

double cross2(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

// The fan triangle holding p (-1 if none); areas in double from the corners.
int fanTriangle(Vec2 p) {
  glm::dvec2 c(FanCentre), q(p);
  for (size_t i = 0; i < FanRim.size(); ++i) {
    glm::dvec2 a(FanRim[i]), b(FanRim[(i + 1) % FanRim.size()]);
    if (cross2(a - c, q - c) >= 0 && cross2(b - a, q - a) >= 0 && cross2(c - b, q - b) >= 0) return int(i);
  }
  return -1;
}

double fanArea(size_t i) {
  glm::dvec2 c(FanCentre), a(FanRim[i]), b(FanRim[(i + 1) % FanRim.size()]);
  return 0.5 * cross2(a - c, b - c);
}

TEST(Shapes, TrianglesArePickedInProportionToArea) {
  Shape mesh = fan();
  std::vector<double> observed(FanRim.size() + 1, 0), expected(FanRim.size() + 1, 0);
  const size_t n = 200000;
  for (size_t i = 0; i < FanRim.size(); ++i) expected[i] = fanArea(i) / 0.6 * n;
  Pcg32 rng(41, 1);
  for (size_t k = 0; k < n; ++k) {
    ShapeSample s = mesh.sampleArea(rng.next1D(), rng.next2D());
    int t = fanTriangle(Vec2(s.p));
    observed[t < 0 ? FanRim.size() : size_t(t)] += 1;  // the last cell: outside the mesh
    ASSERT_EQ(s.pdfArea, 1 / mesh.area());
  }
  auto r = chi2Test(observed, expected);
  EXPECT_TRUE(r.passed(Alpha / Tests)) << r.message << " p=" << r.pValue << " chi2=" << r.statistic;
}

// Emitted positions over the fan, on a 20×12 grid of the rectangle, against
// pdfLe's position density times each cell's area.
TEST(LightEmission, MeshPositionsMatchPdfLe) {
  Shape mesh = fan();
  AreaLight light(&mesh, Color(1.f), false);
  const int nx = 20, ny = 12;
  const size_t n = 300000;
  std::vector<double> observed(nx * ny + 1, 0), expected(nx * ny + 1, 0);
  double mass = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      Vec3 centre(-0.5f + (i + 0.5f) / nx, -0.3f + 0.6f * (j + 0.5f) / ny, 0.f);
      float pdfPos, pdfDir;
      light.pdfLe(centre, Vec3(0, 0, 1), Vec3(0, 0, 1), &pdfPos, &pdfDir);
      double cellMass = double(pdfPos) * (1.0 / nx) * (0.6 / ny);
      expected[size_t(j * nx + i)] = cellMass * n, mass += cellMass;
    }
  expected[nx * ny] = std::max(0.0, 1 - mass) * n;  // outside the rectangle
  Pcg32 rng(42, 1);
  for (size_t k = 0; k < n; ++k) {
    auto e = light.sampleLe(rng.next1D(), rng.next2D(), rng.next2D());
    ASSERT_TRUE(e);
    double x = (double(e->p.x) + 0.5) * nx, y = (double(e->p.y) + 0.3) / 0.6 * ny;
    bool inside = x >= 0 && x < nx && y >= 0 && y < ny;
    observed[inside ? size_t(int(y) * nx + int(x)) : size_t(nx * ny)] += 1;
  }
  auto r = chi2Test(observed, expected);
  EXPECT_TRUE(r.passed(Alpha / Tests)) << r.message << " p=" << r.pValue << " chi2=" << r.statistic;
}

// A spherical emitter: positions (as directions from the centre) against
// pdfLe's area density times r² (area → solid angle on the unit sphere).
TEST(LightEmission, SpherePositionsMatchPdfLe) {
  const float radius = 0.7f;
  const Vec3 centre(0.3f, -0.2f, 2.f);
  Shape ball = Shape::sphere({centre, radius, false});
  AreaLight light(&ball, Color(1.f), false);
  SphereHistogramTest t;
  t.samples = 300000;
  Pcg32 extra(43, 2);
  auto r = t.run(
      [&](Vec2 u, float uPick) -> std::optional<Vec3> {
        auto e = light.sampleLe(uPick, u, extra.next2D());
        if (!e) return std::nullopt;
        return e->p - centre;
      },
      [&](const Vec3& w) {
        float pdfPos, pdfDir;
        light.pdfLe(centre + radius * w, w, w, &pdfPos, &pdfDir);
        return double(pdfPos) * radius * radius;
      },
      43);
  EXPECT_TRUE(r.passed(Alpha / Tests)) << r.message << " p=" << r.pValue << " chi2=" << r.statistic;
}

// The direction density depends on the emitting point's normal: directions
// from three fixed points of the sphere against pdfLe at that point.
TEST(LightEmission, SphereDirectionsMatchPdfLeAtTheirPoint) {
  Shape ball = Shape::sphere({Vec3(0.3f, -0.2f, 2.f), 0.7f, false});
  AreaLight light(&ball, Color(1.f), false);
  const Vec2 positions[] = {{0.1f, 0.2f}, {0.5f, 0.5f}, {0.93f, 0.71f}};
  uint64_t seed = 44;
  for (Vec2 uPos : positions) {
    auto at = light.sampleLe(0.5f, uPos, Vec2(0.5f));
    ASSERT_TRUE(at);
    SphereHistogramTest t;
    t.samples = 200000;
    auto r = t.run(
        [&](Vec2 u, float) -> std::optional<Vec3> {
          auto e = light.sampleLe(0.5f, uPos, u);
          if (!e) return std::nullopt;
          EXPECT_EQ(e->p, at->p);
          return e->ray.d;
        },
        [&](const Vec3& d) {
          float pdfPos, pdfDir;
          light.pdfLe(at->p, at->n, d, &pdfPos, &pdfDir);
          return double(pdfDir);
        },
        seed++);
    EXPECT_TRUE(r.passed(Alpha / Tests / 3)) << "at uPos " << uPos.x << "," << uPos.y << ": " << r.message
                                             << " p=" << r.pValue << " chi2=" << r.statistic;
  }
}

// Unit-disc coordinates of `p` on the disc of radius `radius` centred at
// `centre` perpendicular to `n` (frame of n), after checking that p lies in
// that plane within float rounding (a few ulp of the coordinates' size).
std::optional<Vec2> onDisc(const Vec3& p, const Vec3& centre, const Vec3& n, float radius) {
  glm::dvec3 offset = glm::dvec3(p) - glm::dvec3(centre);
  double rounding = 16 * double(MachineEpsilon) * (glm::length(glm::dvec3(centre)) + 2.0 * radius);
  EXPECT_LE(std::abs(glm::dot(offset, glm::dvec3(n))), rounding) << "origin off the emitting disc's plane";
  Frame f(n);
  return Vec2(float(glm::dot(offset, glm::dvec3(f.s)) / radius), float(glm::dot(offset, glm::dvec3(f.t)) / radius));
}

const Bounds3 SceneBounds{Vec3(-1.f, -2.f, 0.5f), Vec3(3.f, 1.f, 2.f)};

// Parallel rays, all along the light's direction, from a disc covering the
// scene's bounding sphere: origins against pdfLe's position density.
TEST(LightEmission, DirectionalOriginsMatchPdfLe) {
  const Vec3 raw(0.3f, -1.f, 0.2f), direction = glm::normalize(raw);
  DirectionalLight light(raw, Color(1.f));  // normalises raw exactly as above
  light.preprocess(SceneBounds);
  Vec3 centre = SceneBounds.center();
  float radius = SceneBounds.radius();
  DiskHistogramTest t;
  Pcg32 extra(45, 3);
  auto r = t.run(
      [&](Vec2 u) -> std::optional<Vec2> {
        auto e = light.sampleLe(0.5f, u, extra.next2D());
        if (!e) return std::nullopt;
        EXPECT_EQ(e->ray.d, direction);
        return onDisc(e->ray.o, centre - direction * radius, direction, radius);
      },
      [&](Vec2 p) {
        float pdfPos, pdfDir;
        light.pdfLe(centre + radius * Vec3(p, 0.f), direction, direction, &pdfPos, &pdfDir);
        return glm::dot(p, p) < 1 ? double(pdfPos) * radius * radius : 0.0;  // per unit area of the unit disc
      },
      45);
  EXPECT_TRUE(r.passed(Alpha / Tests)) << r.message << " p=" << r.pValue << " chi2=" << r.statistic;
}

// An environment emits inwards from every direction (uniform, against
// pdfLe's direction density), each ray from a disc facing it that covers the
// scene's bounding sphere (against pdfLe's position density).
TEST(LightEmission, EnvironmentRaysMatchPdfLe) {
  EnvironmentLight light(Color(1.f));
  light.preprocess(SceneBounds);
  Vec3 centre = SceneBounds.center();
  float radius = SceneBounds.radius();
  SphereHistogramTest directions;
  directions.samples = 300000;
  auto r = directions.run(
      [&](Vec2 u, float) -> std::optional<Vec3> {
        auto e = light.sampleLe(0.5f, Vec2(0.5f), u);
        if (!e) return std::nullopt;
        return e->ray.d;
      },
      [&](const Vec3& d) {
        float pdfPos, pdfDir;
        light.pdfLe(centre, -d, d, &pdfPos, &pdfDir);
        return double(pdfDir);
      },
      46);
  EXPECT_TRUE(r.passed(Alpha / Tests)) << "directions: " << r.message << " p=" << r.pValue;

  DiskHistogramTest origins;
  Pcg32 extra(47, 4);
  r = origins.run(
      [&](Vec2 u) -> std::optional<Vec2> {
        auto e = light.sampleLe(0.5f, u, extra.next2D());
        if (!e) return std::nullopt;
        return onDisc(e->ray.o, centre - e->ray.d * radius, e->ray.d, radius);
      },
      [&](Vec2 p) {
        float pdfPos, pdfDir;
        light.pdfLe(centre, Vec3(0, 0, 1), Vec3(0, 0, 1), &pdfPos, &pdfDir);
        return glm::dot(p, p) < 1 ? double(pdfPos) * radius * radius : 0.0;
      },
      47);
  EXPECT_TRUE(r.passed(Alpha / Tests)) << "origins: " << r.message << " p=" << r.pValue << " chi2=" << r.statistic;
}

// The pdfs sampleLe reports are pdfLe's for the ray it returned (BDPT's MIS
// and light tracing use both). Point and spot lights emit from their position
// (a delta: sampleLe reports pdfPos 1, pdfLe 0 as in pbrt-v4, since no ray can
// hit them), and a directional light along its direction (pdfDir 1 and 0).
TEST(LightEmission, ReportedPdfsAreThoseOfPdfLe) {
  Shape mesh = fan();
  Shape ball = Shape::sphere({Vec3(0.3f, -0.2f, 2.f), 0.7f, false});
  AreaLight meshLight(&mesh, Color(1.f), false), twoSided(&mesh, Color(1.f), true), sphere(&ball, Color(1.f), false);
  EnvironmentLight env(Color(1.f));
  DirectionalLight sun(Vec3(0.3f, -1.f, 0.2f), Color(1.f));
  env.preprocess(SceneBounds), sun.preprocess(SceneBounds);
  PointLight point(Vec3(1.f, 2.f, 3.f), Color(1.f));
  SpotLight spot(Vec3(1.f, 2.f, 3.f), Vec3(0.2f, 0.3f, 1.f), Color(1.f), 35, 20);
  struct C { const char* name; const Light* light; bool deltaPosition, deltaDirection; };
  const C cases[] = {{"mesh", &meshLight, false, false}, {"mesh two-sided", &twoSided, false, false},
                     {"sphere", &sphere, false, false},  {"environment", &env, false, false},
                     {"directional", &sun, false, true}, {"point", &point, true, false},
                     {"spot", &spot, true, false}};
  Pcg32 rng(48, 5);
  for (const C& c : cases)
    for (int i = 0; i < 2000; ++i) {
      auto e = c.light->sampleLe(rng.next1D(), rng.next2D(), rng.next2D());
      ASSERT_TRUE(e) << c.name;
      float pdfPos, pdfDir;
      c.light->pdfLe(e->p, e->n, e->ray.d, &pdfPos, &pdfDir);
      // Both sides evaluate the same float expressions, except that pdfLe
      // recomputes the cosine from the returned (rotated, rounded) direction:
      // an absolute error of a few ulp of 1 in cos, so of cos/π's scale 1/π.
      if (c.deltaPosition) {
        EXPECT_EQ(e->p, e->ray.o) << c.name;
        EXPECT_EQ(e->pdfPos, 1.f) << c.name;
        EXPECT_EQ(pdfPos, 0.f) << c.name;
      } else {
        ASSERT_NEAR(e->pdfPos, pdfPos, 8 * MachineEpsilon * pdfPos) << c.name;
      }
      if (c.deltaDirection) {
        EXPECT_EQ(e->pdfDir, 1.f) << c.name;
        EXPECT_EQ(pdfDir, 0.f) << c.name;
      } else {
        ASSERT_NEAR(e->pdfDir, pdfDir, 16 * MachineEpsilon * std::max(pdfDir, InvPi)) << c.name;
      }
    }
}

}  // namespace
}  // namespace lb::test
