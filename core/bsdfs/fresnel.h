#pragma once
// Fresnel equations and Snell refraction (pbrt-v4 §9.3, §9.4).
#include <complex>
#include "core/math.h"

namespace lb {

// Unpolarised Fresnel reflectance of a dielectric interface. `eta` is the
// interior IOR over the exterior one; cosThetaI < 0 means arriving from inside.
inline float fresnelDielectric(float cosThetaI, float eta) {
  cosThetaI = glm::clamp(cosThetaI, -1.f, 1.f);
  if (cosThetaI < 0) eta = 1 / eta, cosThetaI = -cosThetaI;
  // cos²θt = 1 - sin²θi/η² = (η² - 1 + cos²θi)/η², evaluated in that form to
  // avoid cancelling 1 - cos²θi near grazing angles.
  float cos2ThetaT = (eta * eta - 1 + cosThetaI * cosThetaI) / (eta * eta);
  if (cos2ThetaT <= 0) return 1.f;  // total internal reflection
  float cosThetaT = std::sqrt(cos2ThetaT);
  float rParl = (eta * cosThetaI - cosThetaT) / (eta * cosThetaI + cosThetaT);
  float rPerp = (cosThetaI - eta * cosThetaT) / (cosThetaI + eta * cosThetaT);
  return (rParl * rParl + rPerp * rPerp) / 2;
}

inline float fresnelComplex(float cosThetaI, std::complex<float> eta) {
  cosThetaI = glm::clamp(cosThetaI, 0.f, 1.f);
  std::complex<float> sin2ThetaT = (1 - cosThetaI * cosThetaI) / (eta * eta);
  std::complex<float> cosThetaT = std::sqrt(1.f - sin2ThetaT);
  std::complex<float> rParl = (eta * cosThetaI - cosThetaT) / (eta * cosThetaI + cosThetaT);
  std::complex<float> rPerp = (cosThetaI - eta * cosThetaT) / (cosThetaI + eta * cosThetaT);
  return (std::norm(rParl) + std::norm(rPerp)) / 2;
}

inline Color fresnelConductor(float cosThetaI, const Color& eta, const Color& k) {
  return {fresnelComplex(cosThetaI, {eta.r, k.r}), fresnelComplex(cosThetaI, {eta.g, k.g}),
          fresnelComplex(cosThetaI, {eta.b, k.b})};
}

inline Vec3 reflect(const Vec3& wo, const Vec3& n) { return -wo + 2 * glm::dot(wo, n) * n; }

// Refracts wi through the interface with normal n (either side); returns false
// on total internal reflection. *etap receives the relative IOR crossed.
inline bool refract(const Vec3& wi, Vec3 n, float eta, float* etap, Vec3* wt) {
  float cosThetaI = glm::dot(n, wi);
  if (cosThetaI < 0) eta = 1 / eta, cosThetaI = -cosThetaI, n = -n;
  float sin2ThetaT = std::max(0.f, 1 - cosThetaI * cosThetaI) / (eta * eta);
  if (sin2ThetaT >= 1) return false;
  float cosThetaT = safeSqrt(1 - sin2ThetaT);
  *wt = -wi / eta + (cosThetaI / eta - cosThetaT) * n;
  if (etap) *etap = eta;
  return true;
}

}  // namespace lb
