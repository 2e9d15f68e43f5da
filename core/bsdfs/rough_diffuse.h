#pragma once
// Rough diffuse reflection: Oren and Nayar's model of a surface of
// V-cavities with Lambertian facets (Oren & Nayar 1994, "Generalization of
// Lambert's Reflectance Model", Eqs. 30 and 39 of its qualitative model), as
// Mitsuba 0.6's `roughdiffuse` evaluates it:
//
//   f = ρ/π [C1 + cos Δφ C2 tan β + (1 − |cos Δφ|) C3 tan((α + β)/2)]
//     + ρ²/π C4 [1 − cos Δφ (2β/π)²]
//
// with α = max(θo, θi), β = min(θo, θi), Δφ the azimuth between the two
// directions and, for the facets' slope deviation σ,
//   C1 = 1 − σ²/(2(σ² + 0.33)),  C2 = 0.45 σ²/(σ² + 0.09) · (sin α if cos Δφ > 0,
//   else sin α − (2β/π)³),  C3 = 0.125 σ²/(σ² + 0.09) · (4αβ/π²)²,
//   C4 = 0.17 σ²/(σ² + 0.13).
// The second line is light scattered twice inside a cavity, hence ρ². σ =
// α_Beckmann/√2: Mitsuba's conversion from the microfacet roughness its other
// BSDFs take (`roughness` here). `fast` is Mitsuba's useFastApprox, the
// model's first-order form A + B max(0, cos Δφ) sin α tan β.
//
// Sampling is cosine-weighted, as Mitsuba's. f is symmetric in its two
// directions, so both transport modes share it; it is not linear in ρ, so the
// texture is applied to ρ here (material.h). Both sides reflect, like
// lightbench's other reflecting materials.
#include "core/bsdfs/material.h"
#include "core/sampling.h"

namespace lb {

class RoughDiffuse final : public Material {
 public:
  RoughDiffuse(const Color& albedo, float roughness, bool fast = false)
      : albedo_(albedo), sigma2_(sqr(roughness / std::sqrt(2.f))), fast_(fast) {}

  BSDFEval eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const override {
    return evalTextured(wo, wi, mode, Color(1.f));
  }
  std::optional<BSDFSample> sample(const Vec3& wo, float uLobe, Vec2 u, TransportMode mode) const override {
    return sampleTextured(wo, uLobe, u, mode, Color(1.f));
  }
  BSDFEval evalTextured(const Vec3& wo, const Vec3& wi, TransportMode, const Color& texture) const override {
    if (wo.z == 0 || wi.z == 0 || !sameHemisphere(wo, wi)) return {};
    return {f(wo, wi, albedo_ * texture), absCosTheta(wi) * InvPi, absCosTheta(wo) * InvPi};
  }
  std::optional<BSDFSample> sampleTextured(const Vec3& wo, float, Vec2 u, TransportMode mode,
                                           const Color& texture) const override {
    if (wo.z == 0) return std::nullopt;
    Vec3 wi = sampleCosineHemisphere(u);
    if (wo.z < 0) wi.z = -wi.z;
    BSDFEval e = evalTextured(wo, wi, mode, texture);
    return BSDFSample{wi, e.f, e.pdf, e.pdfRev, BSDFReflection | BSDFDiffuse};
  }
  float pdf(const Vec3& wo, const Vec3& wi) const override {
    return wo.z != 0 && sameHemisphere(wo, wi) ? absCosTheta(wi) * InvPi : 0.f;
  }
  uint32_t flags() const override { return BSDFReflection | BSDFDiffuse; }

 private:
  Color f(const Vec3& wo, const Vec3& wi, const Color& rho) const {
    float cosO = absCosTheta(wo), cosI = absCosTheta(wi);
    float sinO = safeSqrt(1 - cosO * cosO), sinI = safeSqrt(1 - cosI * cosI);
    // cos Δφ from the directions' projections on the tangent plane.
    float cosPhi = sinO > 1e-4f && sinI > 1e-4f ? glm::clamp((wo.x * wi.x + wo.y * wi.y) / (sinO * sinI), -1.f, 1.f) : 0.f;
    // α is the larger polar angle: its sine; β the smaller: its sine and tangent.
    float sinAlpha = cosI > cosO ? sinO : sinI, sinBeta = cosI > cosO ? sinI : sinO;
    float tanBeta = cosI > cosO ? sinI / cosI : sinO / cosO;
    float s2 = sigma2_;
    if (fast_) {
      float A = 1 - 0.5f * s2 / (s2 + 0.33f), B = 0.45f * s2 / (s2 + 0.09f);
      return rho * (InvPi * (A + B * std::max(cosPhi, 0.f) * sinAlpha * tanBeta));
    }
    float alpha = std::acos(std::min(cosO, cosI)), beta = std::acos(std::max(cosO, cosI));
    float k = s2 / (s2 + 0.09f), twoBetaOverPi = 2 * beta * InvPi, fourAlphaBeta = 4 * InvPi * InvPi * alpha * beta;
    float C1 = 1 - 0.5f * s2 / (s2 + 0.33f);
    float C2 = 0.45f * k * (cosPhi > 0 ? sinAlpha : sinAlpha - twoBetaOverPi * twoBetaOverPi * twoBetaOverPi);
    float C3 = 0.125f * k * fourAlphaBeta * fourAlphaBeta;
    float C4 = 0.17f * s2 / (s2 + 0.13f);
    // tan((α + β)/2) by the half-angle formula, exact from the sines and cosines.
    float tanHalf = (sinAlpha + sinBeta) / (std::min(cosO, cosI) + std::max(cosO, cosI));
    Color single = rho * (C1 + cosPhi * C2 * tanBeta + (1 - std::abs(cosPhi)) * C3 * tanHalf);
    Color twice = rho * rho * (C4 * (1 - cosPhi * twoBetaOverPi * twoBetaOverPi));
    return (single + twice) * InvPi;
  }

  Color albedo_;
  float sigma2_;
  bool fast_;
};

}  // namespace lb
