#pragma once
// Isotropic microfacet distributions: GGX / Trowbridge–Reitz and Beckmann,
// with Smith's masking (Walter et al. 2007, "Microfacet Models for
// Refraction through Rough Surfaces"; Heitz 2014, "Understanding the
// Masking-Shadowing Function"). `alpha` is each one's width parameter.
//
// Sampling: GGX draws visible normals (Heitz 2018, "Sampling the GGX
// Distribution of Visible Normals"; pbrt-v4 §9.6), Beckmann draws normals
// from D(m) cos θm (Walter et al. 2007, Eq. 28: tan²θm = −α² ln(1 − u)).
// pdfNormal() is the density of whichever the distribution samples, so the
// materials need not know which it is.
//
// Masking–shadowing G(wo, wi): the height-correlated form 1/(1 + Λ(wo) + Λ(wi))
// (Heitz 2014, Eq. 99; pbrt-v4) by default, or the separable form
// G1(wo)·G1(wi) (Heitz 2014, Eq. 98) that Mitsuba uses. They differ most at
// grazing angles on rough surfaces (the height-correlated one is up to a third
// brighter at α = 0.5 GGX), so each importer picks its source renderer's
// (docs/scene-format.md); YAML scenes default to height-correlated.
#include <cmath>
#include "core/frame.h"

namespace lb {

enum class MicrofacetKind { GGX, Beckmann };
enum class Masking { HeightCorrelated, Separable };

class Microfacet {
 public:
  explicit Microfacet(float alpha, MicrofacetKind kind = MicrofacetKind::GGX,
                      Masking masking = Masking::HeightCorrelated)
      : alpha_(std::max(alpha, 1e-4f)), kind_(kind), masking_(masking) {}
  float alpha() const { return alpha_; }
  MicrofacetKind kind() const { return kind_; }
  Masking masking() const { return masking_; }

  float D(const Vec3& wm) const {
    float cos2 = wm.z * wm.z;
    float cos4 = cos2 * cos2;
    if (cos4 < 1e-16f) return 0;
    float tan2 = (wm.x * wm.x + wm.y * wm.y) / cos2;  // not (1 - cos²)/cos²: no cancellation near the pole
    float e = tan2 / (alpha_ * alpha_);
    if (kind_ == MicrofacetKind::Beckmann) return std::exp(-e) / (Pi * alpha_ * alpha_ * cos4);
    return 1 / (Pi * alpha_ * alpha_ * cos4 * sqr(1 + e));
  }
  // Smith's Λ (Heitz 2014, Eqs. 72 and 86).
  float lambda(const Vec3& w) const {
    float cos2 = w.z * w.z;
    if (cos2 == 0) return Infinity;
    float tan2 = (w.x * w.x + w.y * w.y) / cos2;
    if (kind_ == MicrofacetKind::GGX) return (std::sqrt(1 + alpha_ * alpha_ * tan2) - 1) / 2;
    if (tan2 == 0) return 0;
    double a = 1 / (double(alpha_) * std::sqrt(double(tan2)));
    return float((std::erf(a) - 1) / 2 + std::exp(-a * a) / (2 * a * std::sqrt(Pi)));
  }
  float G1(const Vec3& w) const { return 1 / (1 + lambda(w)); }
  float G(const Vec3& wo, const Vec3& wi) const {
    if (masking_ == Masking::Separable) return G1(wo) * G1(wi);
    return 1 / (1 + lambda(wo) + lambda(wi));
  }

  // Density of the normal sampleNormal() draws, seen from w (upper hemisphere).
  float pdfNormal(const Vec3& w, const Vec3& wm) const {
    if (kind_ == MicrofacetKind::Beckmann) return D(wm) * absCosTheta(wm);
    // Visible normals (Heitz 2014, Eq. 2).
    float c = absCosTheta(w);
    return c > 0 ? G1(w) / c * D(wm) * absDot(w, wm) : 0;
  }
  Vec3 sampleNormal(const Vec3& w, Vec2 u) const {
    if (kind_ == MicrofacetKind::Beckmann) {
      float tan2 = -alpha_ * alpha_ * std::log1p(-std::min(u.x, 0.99999994f));
      float cosTheta = 1 / std::sqrt(1 + tan2), sinTheta = safeSqrt(1 - cosTheta * cosTheta);
      float phi = 2 * Pi * u.y;
      return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
    }
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
  MicrofacetKind kind_;
  Masking masking_;
};

}  // namespace lb
