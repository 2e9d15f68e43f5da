// The refraction Jacobian in the bidirectional densities (vertex.h) against a
// finite-difference measurement of the refraction map: a small patch of
// directions on one side of a flat interface is mapped through Snell's law
// (written here from the definition, not the material's code) and the solid
// angles of the two patches compared. The walk's reverse density over its
// forward one at a smooth dielectric must equal that area ratio,
// cos θ_air / (η² cos θ_glass) for a path from air into glass.
#include <gtest/gtest.h>
#include <cmath>
#include "core/bsdfs/dielectric.h"
#include "integrators/bidirectional/vertex.h"

namespace lb::test {
namespace {

using DVec3 = glm::dvec3;

// Snell's law for a direction pointing away from the interface z = 0 on the
// side of `w`, refracted to the other side (pointing away from it too);
// `eta` is η(w's side) / η(other side).
DVec3 refractThrough(const DVec3& w, double eta) {
  DVec3 tangential(-w.x * eta, -w.y * eta, 0);
  double s2 = glm::dot(tangential, tangential);
  double z = std::sqrt(1 - s2);
  return DVec3(tangential.x, tangential.y, w.z > 0 ? -z : z);
}

DVec3 polar(double theta, double phi, bool upper) {
  return DVec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), (upper ? 1 : -1) * std::cos(theta));
}

// Solid angle of the small patch (θ ± ε, φ ± ε) around `theta` and of its image, as the
// areas of the quadrilaterals of unit vectors at their corners (exact as ε → 0).
double mappedSolidAngleRatio(double theta, double eta, bool fromUpper, double eps) {
  DVec3 c[4], m[4];
  int k = 0;
  for (double dt : {-eps, eps})
    for (double dp : {-eps, eps}) {
      c[k] = polar(theta + dt, dp, fromUpper);
      m[k] = refractThrough(c[k], eta);
      ++k;
    }
  auto area = [](const DVec3* q) {  // corners 0,1,3,2 in order around the quad
    return 0.5 * glm::length(glm::cross(q[3] - q[0], q[1] - q[2]));
  };
  return area(m) / area(c);
}

// The code's ratio: a walk arriving along `wo` at a smooth dielectric whose
// sample refracts; its reverse density over its forward one.
double codeRatio(const SmoothDielectric& glass, const Vec3& wo) {
  SurfaceInteraction si;
  si.p = Vec3(0.f), si.ng = Vec3(0, 0, 1), si.shading = Frame();
  si.material = &glass, si.wo = wo;
  BSDF bsdf(si);
  for (float u : {0.f, 0.5f, 0.999f})  // the lobe choice: find the transmission
    if (auto bs = bsdf.sample(wo, u, Vec2(0.5f), TransportMode::Importance))
      if (bs->lobe & BSDFTransmission) return double(bidir::reverseDirectionalDensity(si, *bs)) / double(bs->pdf);
  return -1;
}

TEST(RefractionJacobian, ReverseOverForwardDensityIsTheRefractionMapsSolidAngleRatio) {
  for (float ior : {1.5f, 1.33f}) {
    SmoothDielectric glass(ior);
    for (double degrees : {5.0, 30.0, 60.0, 80.0}) {
      double thetaAir = degrees * Pi / 180, thetaGlass = std::asin(std::sin(thetaAir) / ior);
      for (bool fromAir : {true, false}) {
        // From air (above, θ_air) into glass, and back from glass (θ_glass) into air.
        double theta = fromAir ? thetaAir : thetaGlass, eta = fromAir ? 1 / double(ior) : double(ior);
        double fd = mappedSolidAngleRatio(theta, eta, fromAir, 1e-4);
        // The finite difference's own error, from halving its step (Richardson).
        double fdError = std::abs(fd - mappedSolidAngleRatio(theta, eta, fromAir, 5e-5));
        double expected = fromAir ? std::cos(thetaAir) / (double(ior) * ior * std::cos(thetaGlass))
                                  : double(ior) * ior * std::cos(thetaGlass) / std::cos(thetaAir);
        double code = codeRatio(glass, Vec3(polar(theta, 0, fromAir)));
        // The code works in float: a few roundings in each cosine and η².
        double floatError = 64 * std::numeric_limits<float>::epsilon() * expected;
        EXPECT_NEAR(fd, expected, 10 * fdError + 1e-12) << degrees << "°, ior " << ior << (fromAir ? ", from air" : ", from glass");
        EXPECT_NEAR(code, fd, floatError + 10 * fdError)
            << degrees << "°, ior " << ior << (fromAir ? ", from air" : ", from glass") << ": the code's ratio " << code
            << ", the refraction map's " << fd;
      }
    }
  }
}

TEST(RefractionJacobian, IsOneForAReflection) {
  SmoothDielectric glass(1.5f);
  SurfaceInteraction si;
  si.ng = Vec3(0, 0, 1), si.shading = Frame(), si.material = &glass;
  Vec3 wo = glm::normalize(Vec3(0.3f, 0.1f, 0.8f));
  EXPECT_EQ(bidir::refractionJacobian(si, wo, Vec3(-wo.x, -wo.y, wo.z)), 1.f);
}

}  // namespace
}  // namespace lb::test
