// Irradiance-cache records: Ward's weight and interpolation on hand-made
// records, and the Ward–Heckbert gradients against finite differences.
#include <gtest/gtest.h>
#include <cstring>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include "core/scene_loader.h"
#include "integrators/render_loop.h"
#include <yaml-cpp/yaml.h>
#include "integrators/irradiance_cache/irradiance_cache.h"
#include "integrators/irradiance_cache/record_octree.h"
#include "integrators/irradiance_cache/irradiance_cache_integrator.h"
#include "tests/support/render_helpers.h"
#include "tests/support/statistics.h"

namespace lb {
namespace {
using namespace lb::test;

IrradianceRecord flatRecord(Vec3 p, float E, float R) {
  IrradianceRecord r;
  r.p = p, r.n = Vec3(0, 0, 1), r.E = Color(E), r.R = R;
  return r;
}

TEST(WardWeight, FollowsTheFormula) {
  IrradianceRecord r = flatRecord(Vec3(0.f), 1, 2);
  // w = 1 / (|x − xi|/R + sqrt(1 − n·ni))
  EXPECT_FLOAT_EQ(wardWeight(r, Vec3(1, 0, 0), Vec3(0, 0, 1)), 2.f);
  Vec3 tilted = glm::normalize(Vec3(0, std::sin(0.3f), std::cos(0.3f)));
  EXPECT_NEAR(wardWeight(r, Vec3(0.5f, 0, 0), tilted), 1 / (0.25f + std::sqrt(1 - std::cos(0.3f))), 1e-5f);
  EXPECT_TRUE(std::isinf(wardWeight(r, Vec3(0.f), Vec3(0, 0, 1))));
}

TEST(WardWeight, RejectsRecordsInFrontOfThePoint) {
  IrradianceRecord r = flatRecord(Vec3(0, 0, 0.5f), 1, 1);  // lifted above the point's surface
  EXPECT_TRUE(recordInFrontOf(r, Vec3(0.f), Vec3(0, 0, 1)));
  EXPECT_FALSE(recordInFrontOf(r, Vec3(0, 0, 1), Vec3(0, 0, 1)));
}

TEST(Interpolation, WeightsExtrapolatedRecordsByWardsWeight) {
  CacheSettings s;
  s.a = 0.5f;
  s.neighbourClamping = false;  // keep the hand-made radii
  Bounds3 bounds;
  bounds.extend(Vec3(-2.f)), bounds.extend(Vec3(2.f));
  IrradianceCache cache(s, bounds);
  std::vector<LocalRecords> tiles(1);
  IrradianceRecord a = flatRecord(Vec3(0, 0, 0), 1, 1), b = flatRecord(Vec3(0.4f, 0, 0), 3, 2);
  a.translationalGradient = {Vec3(0.5f, 0, 0), Vec3(0.f), Vec3(0.f)};  // red rises along x
  b.rotationalGradient = {Vec3(0.f), Vec3(1, 0, 0), Vec3(0.f)};       // green changes with tilt about x
  tiles[0].records = {a, b};
  cache.merge(tiles);

  Vec3 p(0.2f, 0.1f, 0), n = glm::normalize(Vec3(0, -0.05f, 1));
  float wa = 1 / (glm::length(p - a.p) / 1 + std::sqrt(1 - n.z)), wb = 1 / (glm::length(p - b.p) / 2 + std::sqrt(1 - n.z));
  ASSERT_GT(wa, 2.f);  // both valid for a = 0.5
  ASSERT_GT(wb, 2.f);
  Color Ea(1 + 0.5f * 0.2f, 1, 1), Eb(3, 3 + glm::cross(b.n, n).x, 3);
  Color expected = (wa * Ea + wb * Eb) / (wa + wb);
  Color E;
  LocalRecords none;
  ASSERT_TRUE(cache.interpolate(p, n, none, E));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(E[c], expected[c], 1e-5f * expected[c]) << "channel " << c;

  // Outside every record's reach (w ≤ 1/a) there is no answer.
  EXPECT_FALSE(cache.interpolate(Vec3(1.5f, 0, 0), Vec3(0, 0, 1), none, E));
  // A record facing the other way is never used.
  EXPECT_FALSE(cache.interpolate(Vec3(0.f), Vec3(0, 0, -1), none, E));
}

TEST(Interpolation, ClampingBoundsTheReachAndTheGradient) {
  CacheSettings s;
  s.a = 0.2f, s.spacingInPixels = false, s.minSpacing = 0.1f, s.maxSpacing = 0.5f;
  Bounds3 bounds;
  bounds.extend(Vec3(-1.f)), bounds.extend(Vec3(1.f));
  IrradianceCache cache(s, bounds);
  IrradianceRecord far = flatRecord(Vec3(0.f), 1, 100);
  cache.clampRadius(far, 1);
  EXPECT_FLOAT_EQ(s.a * far.R, 0.5f);
  IrradianceRecord steep = flatRecord(Vec3(0.f), 1, 0.01f);
  steep.translationalGradient = {Vec3(1000, 0, 0), Vec3(0.f), Vec3(0.f)};
  cache.clampRadius(steep, 1);
  EXPECT_FLOAT_EQ(s.a * steep.R, 0.1f);  // the minimum spacing wins over the gradient limit…
  // …and the gradient is shrunk to match: |∇E|·R ≤ E, up to a few ulp of the rescaling.
  EXPECT_LE(glm::length(steep.translationalGradient[0]) * steep.R, 1 + 8 * MachineEpsilon);
}

TEST(RecordOctree, FindsExactlyTheRecordsWhoseCubeContainsAPoint) {
  Bounds3 bounds;
  bounds.extend(Vec3(-1.f)), bounds.extend(Vec3(1.f));
  RecordOctree octree(bounds);
  Pcg32 rng(7, 7);
  std::vector<std::pair<Vec3, float>> balls;
  for (uint32_t i = 0; i < 500; ++i) {
    // Centres on a coarse lattice too, so points and records sit on node midplanes.
    Vec3 c = i % 2 ? 2.f * rng.next2D().x * Vec3(1) - Vec3(1) : Vec3(int(rng.uniformInt(9)) - 4, int(rng.uniformInt(9)) - 4, 0) * 0.25f;
    c.y = i % 3 ? c.y : 2 * rng.next1D() - 1;
    float radius = 0.001f + 0.3f * sqr(rng.next1D());
    balls.push_back({c, radius});
    octree.insert(i, c, radius);
  }
  for (int q = 0; q < 2000; ++q) {
    Vec3 p = q % 2 ? Vec3(2 * rng.next1D() - 1, 2 * rng.next1D() - 1, 2 * rng.next1D() - 1)
                   : Vec3(int(rng.uniformInt(9)) - 4, int(rng.uniformInt(9)) - 4, 0) * 0.25f;
    std::vector<int> seen(balls.size(), 0);
    octree.forEachAt(p, [&](uint32_t id) { ++seen[id]; });
    for (size_t i = 0; i < balls.size(); ++i) {
      Vec3 d = glm::abs(p - balls[i].first);
      bool inCube = d.x <= balls[i].second && d.y <= balls[i].second && d.z <= balls[i].second;
      if (inCube) {
        ASSERT_EQ(seen[i], 1) << "record " << i << " missed or repeated at query " << q;
      }
      ASSERT_LE(seen[i], 1) << "record " << i << " visited twice";
    }
  }
}

TEST(NeighbourClamping, AppliesTheTriangleInequalityBothWays) {
  CacheSettings s;
  s.a = 0.2f;
  Bounds3 bounds;
  bounds.extend(Vec3(-2.f)), bounds.extend(Vec3(2.f));
  IrradianceCache cache(s, bounds);
  std::vector<LocalRecords> tiles(1);
  tiles[0].records = {flatRecord(Vec3(0.f), 1, 5)};  // open floor: large R
  cache.merge(tiles);
  // A corner record 0.5 away: beyond its own R (0.1), but inside the old
  // record's reach (a·R = 1), so only the "reach covers it" search finds it.
  tiles[0].records = {flatRecord(Vec3(0.5f, 0, 0), 1, 0.1f)};
  cache.merge(tiles);
  EXPECT_FLOAT_EQ(cache.records()[0].R, 0.1f + 0.5f);  // the old record shrinks to R_new + d
  EXPECT_FLOAT_EQ(cache.records()[1].R, 0.1f);
  tiles[0].records = {flatRecord(Vec3(1.5f, 0, 0), 1, 5)};  // a new large record beside the small one
  cache.merge(tiles);
  EXPECT_FLOAT_EQ(cache.records()[2].R, 0.1f + 1.0f);  // the new record shrinks to R_small + d
}

// ---- Gradients against finite differences -------------------------------

// A diffuse floor (y = 0) beside an emitting wall (x = 1, facing −x, radiance 1).
const char* const WallScene = R"(
camera: {position: [0, 1, 4], look_at: [0, 0, 0], fov: 40}
film: {width: 8, height: 8}
materials: {white: {type: diffuse, albedo: [0.5, 0.5, 0.5]}}
shapes:
  - {type: rectangle, material: white, transform: {scale: 10, rotate_x: -90}}
  - {type: rectangle, material: white, emission: [1, 1, 1], transform: {rotate_y: -90, translate: [1, 1, 0]}}
)";

struct WallFixture {
  SceneFile sf = loadSceneFromString(WallScene, "wall.yaml");
  // Irradiance from the wall alone: the emitted radiance of whatever is hit.
  IncidentRadiance incident = [this](const Ray& ray, uint64_t) {
    SurfaceInteraction si;
    IncidentSample s;
    if (sf.scene->intersect(ray, si)) {
      s.distance = si.t;
      if (si.emitter) s.L = si.emitter->L(si.ng, si.wo);
    }
    return s;
  };
  IrradianceRecord record(Vec3 p, Vec3 n, uint64_t seed, HemisphereStrata strata) const {
    Pcg32 rng(seed, 3);
    return computeRecord(p, n, strata, rng, [&](const Vec3& d) { return Ray{p + 1e-4f * n, d, Infinity}; }, incident);
  }
};

// Irradiance at p (normal n) from the wall's quad, by Lambert's polygon
// formula E = L/2 Σ θ_i (γ_i · n) (Arvo 1995, Eq. 2).
double analyticWallIrradiance(glm::dvec3 p, glm::dvec3 n) {
  glm::dvec3 quad[4] = {{1, 0, -1}, {1, 2, -1}, {1, 2, 1}, {1, 0, 1}};
  double sum = 0;
  for (int i = 0; i < 4; ++i) {
    glm::dvec3 a = glm::normalize(quad[i] - p), b = glm::normalize(quad[(i + 1) % 4] - p);
    sum += std::acos(glm::clamp(glm::dot(a, b), -1.0, 1.0)) * glm::dot(glm::normalize(glm::cross(a, b)), n);
  }
  return std::abs(sum) / 2;
}

TEST(Gradients, RecordIrradianceMatchesLambertsFormula) {
  WallFixture f;
  Vec3 p(0, 0, 0.3f), n(0, 1, 0);
  RunningStats E;
  for (uint64_t seed = 0; seed < 64; ++seed) E.add(f.record(p, n, seed, {16, 48}).E.r);
  double expected = analyticWallIrradiance(glm::dvec3(p), glm::dvec3(n));
  double z = normalCritical(1e-4);
  // Plus 32 ulp of float rounding, as meanMatches allows for near-zero variance.
  EXPECT_NEAR(E.mean, expected, z * std::sqrt(E.variance() / E.n) + 32 * double(MachineEpsilon) * expected)
      << "σ " << std::sqrt(E.variance());
}

// Ward–Heckbert gradients are finite-strata approximations: against the
// analytic derivative their error here is 13%, 7.5%, 3.7% and 1.9% of |∇E|
// at M = 8, 16, 32, 64 (first order in 1/M). With M = 64 we allow 5% of the
// finite-difference gradient's magnitude (both axes) for it; everything
// beyond is the measured noise of both estimates (64 independent seeds each,
// normal approximation), at a Šidák-corrected level. The rotational
// estimator's tanθ weights make its variance diverge logarithmically at the
// horizon; the stratified samples' measured spread is used as it is.
constexpr double DiscretisationAllowance = 0.05;
constexpr int GradientSeeds = 64;
const HemisphereStrata FineStrata{64, 192};

::testing::AssertionResult agrees(const RunningStats& gradient, const RunningStats& difference, double magnitude,
                                  int comparisons) {
  double z = normalCritical(sidak(1e-3, comparisons));
  double bound = z * std::sqrt(gradient.varianceOfMean() + difference.varianceOfMean()) +
                 DiscretisationAllowance * magnitude;
  double gap = std::abs(gradient.mean - difference.mean);
  if (gap <= bound) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "gradient " << gradient.mean << " vs finite difference " << difference.mean
                                       << ": gap " << gap << " > bound " << bound;
}

RunningStats negated(const RunningStats& s) {
  RunningStats n = s;
  n.mean = -n.mean;
  return n;
}

TEST(Gradients, TranslationalGradientMatchesFiniteDifferences) {
  WallFixture f;
  Vec3 p(0, 0, 0.3f), n(0, 1, 0);
  const float h = 0.02f;  // central-difference truncation, checked on the analytic E: < 0.1% of the gradient
  const Vec3 axes[2] = {Vec3(1, 0, 0), Vec3(0, 0, 1)};
  RunningStats gradient[2], difference[2];
  for (int i = 0; i < 2; ++i)
    for (int k = 0; k < GradientSeeds; ++k) {
      gradient[i].add(glm::dot(f.record(p, n, 100 + k, FineStrata).translationalGradient[0], axes[i]));
      double plus = f.record(p + h * axes[i], n, 200 + k, FineStrata).E.r;
      double minus = f.record(p - h * axes[i], n, 300 + k, FineStrata).E.r;
      difference[i].add((plus - minus) / (2 * h));
    }
  double magnitude = std::hypot(difference[0].mean, difference[1].mean);
  for (int i = 0; i < 2; ++i) {
    EXPECT_TRUE(agrees(gradient[i], difference[i], magnitude, 4)) << "axis " << i;
    EXPECT_FALSE(agrees(negated(gradient[i]), difference[i], magnitude, 4)) << "the check must reject a wrong gradient";
  }
}

TEST(Gradients, RotationalGradientMatchesFiniteDifferences) {
  WallFixture f;
  Vec3 p(0, 0, 0.3f);
  const float alpha = 0.02f;  // radians of tilt
  // Tilting n = +y about an in-plane unit axis a moves it to n + α (a × n);
  // the rotational gradient predicts dE/dα = a · ∇_r E.
  const Vec3 axes[2] = {Vec3(1, 0, 0), Vec3(0, 0, 1)}, n(0, 1, 0);
  RunningStats gradient[2], difference[2];
  for (int i = 0; i < 2; ++i) {
    Vec3 bend = glm::cross(axes[i], n);
    auto tilted = [&](float angle) { return glm::normalize(std::cos(angle) * n + std::sin(angle) * bend); };
    for (int k = 0; k < GradientSeeds; ++k) {
      gradient[i].add(glm::dot(f.record(p, n, 400 + k, FineStrata).rotationalGradient[0], axes[i]));
      double plus = f.record(p, tilted(alpha), 500 + k, FineStrata).E.r;
      double minus = f.record(p, tilted(-alpha), 600 + k, FineStrata).E.r;
      difference[i].add((plus - minus) / (2 * alpha));
    }
  }
  double magnitude = std::hypot(difference[0].mean, difference[1].mean);
  for (int i = 0; i < 2; ++i) {
    EXPECT_TRUE(agrees(gradient[i], difference[i], magnitude, 4)) << "axis " << i;
    EXPECT_FALSE(agrees(negated(gradient[i]), difference[i], magnitude, 4)) << "the check must reject a wrong gradient";
  }
}

}  // namespace
}  // namespace lb
