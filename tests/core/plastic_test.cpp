// Plastic (core/bsdfs/plastic.h) against Mitsuba's definitions, written here
// from its documentation and source independently of the code: the Fresnel
// equations, Beckmann's D and exact Smith G1, the coating's transmittance T(μ)
// and internal reflectance as integrals over the sphere (integrateSphere, not
// the code's Gauss rule in the sampler's square), and the model's formula.
// Sampling against pdf (χ²), sampled weights against eval, reciprocity and
// energy for the rough coating are in bsdfs_test.cpp's cases; the smooth
// coating's delta lobe is checked here.
#include <gtest/gtest.h>
#include "core/bsdfs/plastic.h"
#include "core/rng.h"
#include "tests/support/statistics.h"

namespace lb::test {
namespace {

constexpr double Eta = 1.49 / 1.000277;  // Mitsuba's defaults: polypropylene in air

double fresnel(double cosI, double eta) {  // unpolarised, from the outside if cosI > 0
  if (cosI < 0) eta = 1 / eta, cosI = -cosI;
  double sin2T = (1 - cosI * cosI) / (eta * eta);
  if (sin2T >= 1) return 1;
  double cosT = std::sqrt(1 - sin2T);
  double rs = (cosI - eta * cosT) / (cosI + eta * cosT), rp = (eta * cosI - cosT) / (eta * cosI + cosT);
  return (rs * rs + rp * rp) / 2;
}
// Mitsuba's fresnel_diffuse_reflectance (src/libcore/util, "fast" fits).
double mitsubaFdr(double eta) {
  if (eta < 1) return -1.4399 * eta * eta + 0.7099 * eta + 0.6681 + 0.0636 / eta;
  double x = 1 / eta;
  return 0.919317 - 3.4793 * x + 6.75335 * x * x - 7.80989 * std::pow(x, 3) + 4.98554 * std::pow(x, 4) -
         1.36881 * std::pow(x, 5);
}
double beckmannD(const glm::dvec3& m, double a) {
  if (m.z <= 0) return 0;
  double c2 = m.z * m.z, tan2 = (1 - c2) / c2;
  return std::exp(-tan2 / (a * a)) / (Pi * a * a * c2 * c2);
}
double beckmannG1(const glm::dvec3& v, double a) {  // Smith, exact (Walter et al. 2007, Eq. 25)
  double tanT = std::sqrt(std::max(0.0, 1 - v.z * v.z)) / v.z;
  if (tanT == 0) return 1;
  double x = 1 / (a * tanT);
  return 2 / (1 + std::erf(x) + std::exp(-x * x) / (x * std::sqrt(Pi)));
}
// Mitsuba's rough coating, f·cos θo, separable masking, specular factor 1.
double coatCos(const glm::dvec3& wi, const glm::dvec3& wo, double a, double eta) {
  if (wi.z <= 0 || wo.z <= 0) return 0;
  glm::dvec3 h = glm::normalize(wi + wo);
  return beckmannD(h, a) * fresnel(glm::dot(wi, h), eta) * beckmannG1(wi, a) * beckmannG1(wo, a) / (4 * wi.z);
}
glm::dvec3 dirAt(double mu, double phi = 0) {
  double s = std::sqrt(std::max(0.0, 1 - mu * mu));
  return {s * std::cos(phi), s * std::sin(phi), mu};
}
// The rough interface's shares, from their definitions as integrals over the
// outgoing direction (Walter et al. 2007, Eqs. 17 and 21; separable masking),
// for light arriving at cos θ = μ: the flux it reflects, and the flux it
// refracts (the η² of the transmission Jacobian, not of radiance).
double reflectedShare(double mu, double a, double eta, double tolerance) {
  glm::dvec3 wi = dirAt(mu);
  Frame around(Vec3(-float(wi.x), 0.f, float(wi.z)));  // the mirror direction, where the lobe is
  return integrateSphere([&](const Vec3& w) { return glm::dvec3(coatCos(wi, glm::dvec3(w), a, eta)); }, tolerance,
                         16, 32, around).value.x;
}
double refractedShare(double mu, double a, double eta) {
  glm::dvec3 wi = dirAt(mu);
  auto integrand = [&](const Vec3& w) {
    glm::dvec3 o(w);
    if (o.z >= 0) return glm::dvec3(0.0);
    glm::dvec3 h = -(wi + eta * o);
    if (glm::dot(h, h) == 0) return glm::dvec3(0.0);
    h = glm::normalize(h);
    if (h.z < 0) h = -h;
    double ih = glm::dot(wi, h), oh = glm::dot(o, h);
    if (ih <= 0 || oh >= 0) return glm::dvec3(0.0);
    double jacobian = eta * eta * std::abs(oh) / std::pow(ih + eta * oh, 2);
    double visible = beckmannG1(wi, a) * beckmannD(h, a) * ih / wi.z;
    return glm::dvec3(visible * (1 - fresnel(ih, eta)) * beckmannG1(-o, a) * jacobian);
  };
  double sinT = wi.x / eta;  // Snell: the lobe is around the straight refraction
  Frame around(Vec3(float(-sinT), 0.f, float(-std::sqrt(1 - sinT * sinT))));
  return integrateSphere(integrand, 1e-6, 16, 32, around).value.x;
}

// Smooth plastic: f = ρ/(1 − F_dr(1/η)) · η⁻² (1 − F(μo)) (1 − F(μi)) / π
// (nonlinear: ρ/(1 − ρ F_dr(1/η))), plus a mirror reflection of weight
// specular · F(μo), chosen with probability F·w / (F·w + (1 − F)(1 − w)).
TEST(Plastic, SmoothMatchesMitsubasFormulas) {
  const Color rho(0.2f, 0.5f, 0.8f), spec(0.9f, 1.f, 1.f);
  for (bool nonlinear : {false, true}) {
    PlasticParams p;
    p.diffuse = p.diffuseMean = rho, p.specular = spec, p.eta = float(Eta), p.nonlinear = nonlinear;
    Plastic plastic(p);
    double fdr = mitsubaFdr(1 / Eta);
    double w = (0.9 + 1 + 1) / 3 / ((0.9 + 1 + 1) / 3 + (0.2 + 0.5 + 0.8) / 3);
    for (double muO : {1.0, 0.7, 0.3, 0.05})
      for (double muI : {0.9, 0.5, 0.1}) {
        Vec3 wo(dirAt(muO, 0.3)), wi(dirAt(muI, 2.0));
        BSDFEval e = plastic.eval(wo, wi, TransportMode::Radiance);
        double Fo = fresnel(muO, Eta), Fi = fresnel(muI, Eta);
        for (int k = 0; k < 3; ++k) {
          double base = nonlinear ? rho[k] / (1 - rho[k] * fdr) : rho[k] / (1 - fdr);
          double f = base / (Eta * Eta) * (1 - Fo) * (1 - Fi) / Pi;
          EXPECT_NEAR(e.f[k], f, 1e-5 * f) << "muO " << muO << " muI " << muI;
        }
        double pCoat = Fo * w / (Fo * w + (1 - Fo) * (1 - w));
        EXPECT_NEAR(e.pdf, (1 - pCoat) * muI / Pi, 1e-5 * e.pdf);
        // The mirror: uLobe below the coat's probability picks it.
        auto s = plastic.sample(wo, float(pCoat) * 0.999f, Vec2(0.5f), TransportMode::Radiance);
        ASSERT_TRUE(s && s->isDelta());
        EXPECT_NEAR(s->pdf, pCoat, 1e-5 * pCoat);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(s->weight()[k], spec[k] * Fo / pCoat, 1e-5 * spec[k] * Fo / pCoat);
        EXPECT_NEAR(s->wi.z, wo.z, 1e-6f);
        EXPECT_NEAR(s->wi.x, -wo.x, 1e-6f);
      }
  }
}

// The coating's transmittance T(μ), at the table's nodes and between them
// (Mitsuba interpolates linearly too), and the internal reflectance by
// Mitsuba 3's rule F_int = 2 · mean over the 64 nodes of R(μ; 1/η) μ, against
// the shares integrated over the sphere. Allowance 1e-3 absolute: the code's
// Gauss rule in the sampler's square is cut by the horizon, so it converges
// slowly where the lobe meets it; 1e-3 of T is below what an image
// comparison resolves (a 0.1 % change of the base).
TEST(Plastic, RoughCoatingTransmittanceMatchesItsIntegral) {
  const int last = Plastic::TableSize - 1;
  for (double a : {0.1, 0.3}) {
    PlasticParams p;
    p.alpha = float(a), p.eta = float(Eta), p.kind = MicrofacetKind::Beckmann, p.masking = Masking::Separable;
    Plastic plastic(p);
    for (int k : {1, 8, 20, 40, 63}) {
      double mu = double(k) / last;
      EXPECT_NEAR(plastic.transmittance(float(mu)), refractedShare(mu, a, Eta), 1e-3) << "a " << a << " mu " << mu;
    }
    double interpolated = (refractedShare(30.0 / last, a, Eta) + refractedShare(31.0 / last, a, Eta)) / 2;
    EXPECT_NEAR(plastic.transmittance(float(30.5 / last)), interpolated, 1e-3) << "a " << a;
  }
  PlasticParams p;
  p.alpha = 0.3f, p.eta = float(Eta), p.kind = MicrofacetKind::Beckmann, p.masking = Masking::Separable;
  double internal = 0;
  for (int k = 0; k <= last; ++k) {
    double mu = std::max(1e-6, double(k) / last);
    internal += reflectedShare(mu, 0.3, 1 / Eta, 1e-5) * mu;
  }
  EXPECT_NEAR(Plastic(p).internalReflectance(), 2 * internal / (last + 1), 1e-3);
}

// Rough plastic's f at several direction pairs: the coating D F G1 G1 /
// (4 μo μi) plus the base ρ/(1 − F_int) η⁻² T(μo) T(μi) / π, with T and F_int
// taken from the code (checked above) so the formula is checked on its own;
// only the diffuse base is textured.
TEST(Plastic, RoughMatchesMitsubasFormulaAndTexturesOnlyTheBase) {
  const double a = 0.2;
  const Color rho(0.3f, 0.6f, 0.9f), texture(0.5f, 1.f, 0.25f);
  for (bool nonlinear : {false, true}) {
    PlasticParams p;
    p.diffuse = p.diffuseMean = rho, p.alpha = float(a), p.eta = float(Eta), p.nonlinear = nonlinear;
    p.kind = MicrofacetKind::Beckmann, p.masking = Masking::Separable;
    Plastic plastic(p);
    double fint = plastic.internalReflectance();
    Pcg32 rng(7, 1);
    for (int n = 0; n < 200; ++n) {
      glm::dvec3 wo = dirAt(0.02 + 0.98 * rng.next1D(), 0), wi = dirAt(0.02 + 0.98 * rng.next1D(), 2 * Pi * rng.next1D());
      BSDFEval plain = plastic.eval(Vec3(wo), Vec3(wi), TransportMode::Radiance);
      BSDFEval textured = plastic.evalTextured(Vec3(wo), Vec3(wi), TransportMode::Radiance, texture);
      double coat = coatCos(wo, wi, a, Eta) / wi.z;
      double T = double(plastic.transmittance(float(wo.z))) * plastic.transmittance(float(wi.z));
      for (int k = 0; k < 3; ++k)
        for (double t : {1.0, double(texture[k])}) {
          double r = rho[k] * t;
          double base = (nonlinear ? r / (1 - r * fint) : r / (1 - fint)) / (Eta * Eta) * T / Pi;
          double got = t == 1.0 ? plain.f[k] : textured.f[k];
          // float D, G1 (erf) and Fresnel: a few ulp each, 1e-4 relative in all.
          EXPECT_NEAR(got, coat + base, 1e-4 * (coat + base)) << "wo.z " << wo.z << " wi.z " << wi.z << " t " << t;
        }
      EXPECT_EQ(plain.pdf, textured.pdf);  // sampling does not see the texture (material.h)
    }
  }
}

// Smooth plastic's sampled weights: their mean is the albedo, F·specular from
// the mirror plus ∫ f cos over the base, the latter integrated over the sphere
// from eval(). White base, linear form: the albedo is F + (1 − F) η⁻² (1 −
// F_dr(η)) / (1 − F_dr(1/η)) — 1 up to the fits — and never above 1 beyond that.
TEST(Plastic, SmoothSampledWeightsAverageToTheAlbedo) {
  PlasticParams p;
  p.diffuse = p.diffuseMean = Color(1.f), p.eta = float(Eta);
  Plastic plastic(p);
  for (double mu : {0.95, 0.5, 0.1}) {
    Vec3 wo(dirAt(mu, 1.0));
    RunningStats mean;
    Pcg32 rng(uint64_t(mu * 100), 5);
    for (int i = 0; i < 200000; ++i) {
      auto s = plastic.sample(wo, rng.next1D(), rng.next2D(), TransportMode::Radiance);
      mean.add(s ? double(s->weight().r) : 0.0);
    }
    SphereIntegral base = integrateSphere(
        [&](const Vec3& wi) { return glm::dvec3(plastic.eval(wo, wi, TransportMode::Radiance).f.r * std::abs(wi.z)); }, 1e-7);
    double albedo = fresnel(mu, Eta) + base.value.x;
    double z = normalCritical(0.01 / 3);
    EXPECT_NEAR(mean.mean, albedo, z * std::sqrt(mean.varianceOfMean()) + base.error.x + 1e-6) << "mu " << mu;
    // The model's own energy balance, with the fits' quoted 0.1 % each.
    double expected = fresnel(mu, Eta) + (1 - fresnel(mu, Eta)) / (Eta * Eta) * (1 - mitsubaFdr(Eta)) / (1 - mitsubaFdr(1 / Eta));
    EXPECT_NEAR(albedo, expected, 0.003 * expected) << "mu " << mu;
  }
}

}  // namespace
}  // namespace lb::test
