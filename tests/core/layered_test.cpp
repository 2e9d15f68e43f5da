// pbrt-v4's layered BSDFs (core/bsdfs/layered.h): the walk against what the
// stack is known to do where it can be worked out (an index-matched coating
// is the base seen through the layer's absorption; a smooth coating over a
// Lambertian base sums its inter-reflections in closed form, Mitsuba's
// nonlinear plastic written here from the Fresnel equations), its sampled
// weights against its evaluated f (two different random walks for one
// albedo), and path tracing and BDPT agreeing on a scene of coated materials.
#include <gtest/gtest.h>
#include <cmath>
#include "core/bsdfs/layered.h"
#include "core/bsdfs/material_factory.h"
#include "core/params.h"
#include "core/rng.h"
#include "core/scene_loader.h"
#include "tests/support/render_helpers.h"
#include "tests/support/repeats.h"
#include "tests/support/statistics.h"

namespace lb::test {
namespace {

std::unique_ptr<Material> material(const std::string& yaml) {
  Params p(YAML::Load(yaml), "test.yaml", "materials.m");
  return makeMaterial(p);
}
const Layered& layered(const Material& m) { return dynamic_cast<const Layered&>(m); }

Vec3 dirAt(double mu, double phi) {
  double s = std::sqrt(std::max(0.0, 1 - mu * mu));
  return Vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(mu));
}

double fresnel(double cosI, double eta) {  // unpolarised, from the side cosI > 0 points to
  if (cosI < 0) eta = 1 / eta, cosI = -cosI;
  double sin2T = (1 - cosI * cosI) / (eta * eta);
  if (sin2T >= 1) return 1;
  double cosT = std::sqrt(1 - sin2T);
  double rs = (cosI - eta * cosT) / (cosI + eta * cosT), rp = (eta * cosI - cosT) / (eta * cosI + cosT);
  return (rs * rs + rp * rp) / 2;
}

const std::vector<std::pair<double, double>> Angles = {{0.9, 0.8}, {0.5, 0.95}, {0.2, 0.6}, {0.7, 0.3}};

TEST(Layered, AnIndexMatchedCoatingShowsTheBaseThroughTheLayer) {
  // Index 1: the coating neither reflects nor bends; what is left is the base,
  // ρ/π, attenuated by exp(−h/μ) on the way in and on the way out.
  auto m = material("{type: coated_diffuse, albedo: 0.6, ior: 1, thickness: 0.3}");
  for (auto [muO, muI] : Angles)
    for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
      Color f = layered(*m).f(dirAt(muO, 0.3), dirAt(muI, 2.0), mode, Color(1.f));
      double want = 0.6 / Pi * std::exp(-0.3 / muO) * std::exp(-0.3 / muI);
      EXPECT_NEAR(f.g, want, 1e-5 * want) << "mu_o " << muO << " mu_i " << muI;
    }
}

// A smooth coating of index η over a Lambertian base ρ, with a layer too thin
// to absorb: light refracts in (1 − F(μo)), is reflected diffusely, and each
// time it reaches the coating from below a share F_int (the cosine-weighted
// mean of the internal Fresnel reflectance) returns to the base, so
// f = (1 − F(μo)) (1 − F(μi)) ρ / (π η² (1 − ρ F_int)). The walk estimates
// this; its mean over hashes (wi jittered by 1e-5) must match within 4
// standard errors. max_depth is raised so truncation is below 1e-9.
TEST(Layered, ASmoothCoatingSumsTheInterReflectionsOfAPlastic) {
  const double eta = 1.5, rho = 0.5;
  auto m = material("{type: coated_diffuse, albedo: 0.5, ior: 1.5, thickness: 1e-7, max_depth: 100}");
  double fInt = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    double mu = (i + 0.5) / n;
    fInt += 2 * fresnel(-mu, eta) * mu / n;  // from inside: cosI < 0 side
  }
  Pcg32 rng(3, 1);
  for (auto [muO, muI] : Angles) {
    double want = (1 - fresnel(muO, eta)) * (1 - fresnel(muI, eta)) * rho / (Pi * eta * eta * (1 - rho * fInt));
    RunningStats stats;
    for (int k = 0; k < 20000; ++k) {
      Vec3 wi = dirAt(muI + 1e-5 * (rng.next1D() - 0.5), 2.0 + 1e-5 * rng.next1D());
      stats.add(layered(*m).f(dirAt(muO, 0.3), wi, TransportMode::Radiance, Color(1.f)).g);
    }
    double se = std::sqrt(stats.varianceOfMean());
    EXPECT_NEAR(stats.mean, want, 4 * se + 1e-4 * want) << "mu_o " << muO << " mu_i " << muI << " (se " << se << ")";
  }
}

// The albedo ∫ f |cos θi| dωi two ways: the mean of sample()'s weights (one
// walk each, the directions it finds) and a uniform-hemisphere estimate of
// the integral of eval()'s f (the walk joined to wi by next-event
// estimation). Different walks, one quantity: a z-test at 1e-4 per case.
TEST(Layered, SampledWeightsAverageToTheIntegralOfEvaluatedF) {
  for (const char* yaml : {"{type: coated_diffuse, albedo: 0.7, ior: 1.5, roughness: 0.3}",
                           "{type: coated_diffuse, albedo: [0.9, 0.5, 0.2], ior: 1.3, roughness: 0.05, thickness: 0.1}",
                           "{type: coated_conductor, ior: 1.5, roughness: 0.2, conductor_roughness: 0.4}",
                           "{type: coated_conductor, ior: 1.5, roughness: 0.3}"}) {
    auto m = material(yaml);
    Pcg32 rng(17, 2);
    for (double muO : {0.9, 0.4}) {
      Vec3 wo = dirAt(muO, 0.7);
      RunningStats sampled, integrated;
      for (int k = 0; k < 40000; ++k) {
        auto s = m->sample(wo, rng.next1D(), Vec2(rng.next1D(), rng.next1D()), TransportMode::Radiance);
        sampled.add(s ? s->weight().g : 0.0);
        Vec3 wi = sampleUniformHemisphere(Vec2(rng.next1D(), rng.next1D()));
        integrated.add(m->eval(wo, wi, TransportMode::Radiance).f.g * wi.z * 2 * Pi);
      }
      double se = std::sqrt(sampled.varianceOfMean() + integrated.varianceOfMean());
      EXPECT_NEAR(sampled.mean, integrated.mean, 3.9 * se) << yaml << " mu_o " << muO;
      EXPECT_LE(sampled.mean, 1.0 + 3.9 * se) << yaml << ": more light out than in";
    }
  }
}

TEST(Layered, PdfIsPositiveAboveAndZeroBelow) {
  auto m = material("{type: coated_diffuse, roughness: 0.2}");
  Vec3 wo = dirAt(0.6, 0.1);
  EXPECT_GT(m->pdf(wo, dirAt(0.3, 2.0)), 0.1f * Inv4Pi * 0.99f);
  EXPECT_EQ(m->pdf(wo, dirAt(-0.3, 2.0)), 0.f);
  EXPECT_EQ(layered(*m).f(wo, dirAt(-0.3, 2.0), TransportMode::Radiance, Color(1.f)), Color(0.f));
}

// A smooth coating (η = 1.5) over a smooth metal, seen head-on: the coating
// reflects F0 = ((η − 1)/(η + 1))², and the light that enters bounces between
// metal and coating, leaving T = 1 − F0 each time it meets the coating, so
// the albedo is F0 + T² Rc / (1 − F0 Rc). The metal's Rc at normal incidence
// is ((n − 1)² + k²)/((n + 1)² + k²) with its indices relative to the
// coating's, n = 0.3/1.5 and k = 3/1.5 (pbrt-v4's coatedconductor divides
// them so). Mean of sample()'s weights, 4 standard errors.
TEST(Layered, ACoatedMirrorReflectsWhatItsLayersSumTo) {
  auto m = material("{type: coated_conductor, ior: 1.5, conductor_eta: 0.3, conductor_k: 3, thickness: 1e-7, max_depth: 400}");
  const double f0 = 0.04, n = 0.3 / 1.5, k = 3 / 1.5;
  const double rc = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
  const double want = f0 + (1 - f0) * (1 - f0) * rc / (1 - f0 * rc);
  Pcg32 rng(5, 3);
  RunningStats weights;
  for (int i = 0; i < 40000; ++i) {
    auto s = m->sample(Vec3(0, 0, 1), rng.next1D(), Vec2(rng.next1D(), rng.next1D()), TransportMode::Radiance);
    weights.add(s ? s->weight().g : 0.0);
  }
  EXPECT_NEAR(weights.mean, want, 4 * std::sqrt(weights.varianceOfMean()) + 1e-6);
  EXPECT_TRUE(m->isDelta()) << "smooth on smooth: every walk is specular";
}

// Path tracing and BDPT on a box with a rough-coated diffuse sphere, a
// coated rough conductor and a smooth-coated floor: BDPT's light subpaths
// evaluate the walks in importance mode and its MIS uses pdf() both ways.
TEST(Layered, PathAndBdptAgreeOnCoatedMaterials) {
  SceneFile f = loadSceneFromString(
      "camera: {position: [0, 1, 3.4], look_at: [0, 0.8, 0], fov: 50}\n"
      "film: {width: 24, height: 24}\n"
      "integrator: {name: path, max_depth: 6}\n"
      "materials:\n"
      "  wall: {type: diffuse, albedo: 0.6}\n"
      "  floor: {type: coated_diffuse, albedo: [0.7, 0.4, 0.2], ior: 1.5}\n"
      "  ball: {type: coated_diffuse, albedo: [0.2, 0.5, 0.8], ior: 1.5, roughness: 0.2}\n"
      "  metal: {type: coated_conductor, ior: 1.5, roughness: 0.1, conductor_roughness: 0.3}\n"
      "shapes:\n"
      "  - {type: rectangle, material: floor, transform: {scale: 2, rotate_x: -90}}\n"
      "  - {type: rectangle, material: wall, transform: {scale: 2, translate: [0, 1, -2]}}\n"
      "  - {type: sphere, material: ball, center: [-0.6, 0.5, 0], radius: 0.5}\n"
      "  - {type: sphere, material: metal, center: [0.6, 0.5, -0.3], radius: 0.5}\n"
      "  - {type: rectangle, material: none, emission: 8, transform: {scale: 0.4, rotate_x: 90, translate: [0, 2, 0]}}\n",
      "coated.yaml");
  std::string failures = pathBdptDisagreement(f, 256, 1e-3, 6);
  EXPECT_TRUE(failures.empty()) << failures;
}

}  // namespace
}  // namespace lb::test
