#pragma once
// Isotropic GGX / Trowbridge–Reitz distribution with visible-normal sampling
// (Heitz 2018, "Sampling the GGX Distribution of Visible Normals"; the
// formulation follows pbrt-v4 §9.6). `alpha` is the GGX width parameter.
#include "core/frame.h"

namespace lb {

class GGX {
 public:
  explicit GGX(float alpha) : alpha_(std::max(alpha, 1e-4f)) {}
  float alpha() const { return alpha_; }

  float D(const Vec3& wm) const {
    float cos2 = wm.z * wm.z;
    float cos4 = cos2 * cos2;
    if (cos4 < 1e-16f) return 0;
    float tan2 = (wm.x * wm.x + wm.y * wm.y) / cos2;  // not (1 - cos²)/cos²: no cancellation near the pole
    float e = tan2 / (alpha_ * alpha_);
    return 1 / (Pi * alpha_ * alpha_ * cos4 * sqr(1 + e));
  }
  float lambda(const Vec3& w) const {
    float cos2 = w.z * w.z;
    if (cos2 == 0) return Infinity;
    float tan2 = (w.x * w.x + w.y * w.y) / cos2;
    return (std::sqrt(1 + alpha_ * alpha_ * tan2) - 1) / 2;
  }
  float G1(const Vec3& w) const { return 1 / (1 + lambda(w)); }
  float G(const Vec3& wo, const Vec3& wi) const { return 1 / (1 + lambda(wo) + lambda(wi)); }
  // Density of visible normals seen from w (Heitz 2014, Eq. 2).
  float visibleD(const Vec3& w, const Vec3& wm) const {
    float c = absCosTheta(w);
    return c > 0 ? G1(w) / c * D(wm) * absDot(w, wm) : 0;
  }
  Vec3 sampleVisibleNormal(const Vec3& w, Vec2 u) const {
    Vec3 wh = glm::normalize(Vec3(alpha_ * w.x, alpha_ * w.y, w.z));
    if (wh.z < 0) wh = -wh;
    Vec3 t1 = wh.z < 0.99999f ? glm::normalize(glm::cross(Vec3(0, 0, 1), wh)) : Vec3(1, 0, 0);
    Vec3 t2 = glm::cross(wh, t1);
    float r = std::sqrt(u.x), phi = 2 * Pi * u.y;
    Vec2 p(r * std::cos(phi), r * std::sin(phi));
    float h = std::sqrt(1 - p.x * p.x);
    float s = (1 + wh.z) / 2;
    p.y = (1 - s) * h + s * p.y;
    float pz = safeSqrt(1 - glm::dot(p, p));
    Vec3 nh = p.x * t1 + p.y * t2 + pz * wh;
    return glm::normalize(Vec3(alpha_ * nh.x, alpha_ * nh.y, std::max(1e-6f, nh.z)));
  }

 private:
  float alpha_;
};

}  // namespace lb
