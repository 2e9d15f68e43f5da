#pragma once
// Lambertian reflection, f = ρ/π, cosine-weighted sampling on wo's side.
#include "core/bsdfs/material.h"
#include "core/sampling.h"

namespace lb {

class Diffuse final : public Material {
 public:
  explicit Diffuse(const Color& albedo) : albedo_(albedo) {}

  BSDFEval eval(const Vec3& wo, const Vec3& wi, TransportMode) const override {
    if (!sameHemisphere(wo, wi)) return {};
    return {albedo_ * InvPi, absCosTheta(wi) * InvPi, absCosTheta(wo) * InvPi};
  }
  std::optional<BSDFSample> sample(const Vec3& wo, float, Vec2 u, TransportMode) const override {
    if (wo.z == 0) return std::nullopt;
    Vec3 wi = sampleCosineHemisphere(u);
    if (wo.z < 0) wi.z = -wi.z;
    if (wi.z == 0) return std::nullopt;
    return BSDFSample{wi, albedo_ * InvPi, absCosTheta(wi) * InvPi, absCosTheta(wo) * InvPi,
                      BSDFReflection | BSDFDiffuse};
  }
  float pdf(const Vec3& wo, const Vec3& wi) const override {
    return sameHemisphere(wo, wi) ? absCosTheta(wi) * InvPi : 0.f;
  }
  uint32_t flags() const override { return BSDFReflection | BSDFDiffuse; }

 private:
  Color albedo_;
};

}  // namespace lb
