// Oren–Nayar (core/bsdfs/rough_diffuse.h) against the model as written in
// Oren & Nayar 1994 (Eqs. 30 and 39, with the C1–C3 of their qualitative
// model and Mitsuba 0.6's σ = α/√2), evaluated here from the angles
// themselves (acos, atan2, tan of the half sum) rather than the code's
// sines and half-angle identity. Sampling against pdf (χ²), sampled weights
// against eval, reciprocity and energy are in bsdfs_test.cpp's cases.
#include <gtest/gtest.h>
#include "core/bsdfs/rough_diffuse.h"
#include "core/rng.h"

namespace lb::test {
namespace {

double orenNayar(double rho, double alphaRoughness, double thetaO, double phiO, double thetaI, double phiI, bool fast) {
  double s2 = alphaRoughness * alphaRoughness / 2;
  double a = std::max(thetaO, thetaI), b = std::min(thetaO, thetaI);
  double cosPhi = std::cos(phiO - phiI);
  if (fast) {
    double A = 1 - 0.5 * s2 / (s2 + 0.33), B = 0.45 * s2 / (s2 + 0.09);
    return rho / Pi * (A + B * std::max(0.0, cosPhi) * std::sin(a) * std::tan(b));
  }
  double C1 = 1 - 0.5 * s2 / (s2 + 0.33);
  double C2 = cosPhi > 0 ? 0.45 * s2 / (s2 + 0.09) * std::sin(a)
                         : 0.45 * s2 / (s2 + 0.09) * (std::sin(a) - std::pow(2 * b / Pi, 3));
  double C3 = 0.125 * s2 / (s2 + 0.09) * std::pow(4 * a * b / (Pi * Pi), 2);
  double single = rho / Pi * (C1 + cosPhi * C2 * std::tan(b) + (1 - std::abs(cosPhi)) * C3 * std::tan((a + b) / 2));
  double twice = 0.17 * rho * rho / Pi * s2 / (s2 + 0.13) * (1 - cosPhi * std::pow(2 * b / Pi, 2));
  return single + twice;
}

Vec3 direction(double theta, double phi) {
  return {float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)), float(std::cos(theta))};
}

TEST(RoughDiffuse, MatchesOrenNayarsModelAndTexturesItsAlbedo) {
  const Color rho(0.9f, 0.5f, 0.2f), texture(0.5f, 1.f, 0.8f);
  Pcg32 rng(17, 3);
  for (bool fast : {false, true})
    for (float roughness : {0.1f, 0.4f, 1.f}) {
      RoughDiffuse m(rho, roughness, fast);
      for (int n = 0; n < 300; ++n) {
        double thetaO = 1.5 * rng.next1D(), thetaI = 1.5 * rng.next1D();
        double phiO = 2 * Pi * rng.next1D(), phiI = 2 * Pi * rng.next1D();
        Vec3 wo = direction(thetaO, phiO), wi = direction(thetaI, phiI);
        Color f = m.eval(wo, wi, TransportMode::Radiance).f;
        Color ft = m.evalTextured(wo, wi, TransportMode::Radiance, texture).f;
        for (int k = 0; k < 3; ++k) {
          double expected = orenNayar(rho[k], roughness, thetaO, phiO, thetaI, phiI, fast);
          double textured = orenNayar(rho[k] * texture[k], roughness, thetaO, phiO, thetaI, phiI, fast);
          // Float sines, acos and a division by cos θ up to 1.5 rad: 1e-5 relative.
          EXPECT_NEAR(f[k], expected, 1e-5 * expected + 1e-7) << "fast " << fast << " roughness " << roughness;
          EXPECT_NEAR(ft[k], textured, 1e-5 * textured + 1e-7);
        }
        // The back side is the same surface (two-sided, as every reflector here).
        Vec3 woBack(wo.x, wo.y, -wo.z), wiBack(wi.x, wi.y, -wi.z);
        EXPECT_EQ(m.eval(woBack, wiBack, TransportMode::Radiance).f, f);
      }
    }
  // No roughness is Lambert's law.
  RoughDiffuse smooth(rho, 0.f);
  EXPECT_NEAR(smooth.eval(direction(0.3, 0), direction(1.1, 2), TransportMode::Radiance).f.r, rho.r / Pi, 1e-7);
}

}  // namespace
}  // namespace lb::test
