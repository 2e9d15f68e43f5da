#pragma once
// Conductors: a smooth mirror (delta) and a rough (GGX or Beckmann) conductor. Fresnel uses
// the complex IOR (eta, k) when given; otherwise reflectance is `tint` alone.
#include "core/bsdfs/fresnel.h"
#include "core/bsdfs/material.h"
#include "core/bsdfs/microfacet.h"

namespace lb {

struct ConductorFresnel {
  Color tint{1.f};
  bool complexIor = false;
  Color eta{1.f}, k{0.f};
  Color operator()(float cosTheta) const {
    return complexIor ? tint * fresnelConductor(cosTheta, eta, k) : tint;
  }
};

class SmoothConductor final : public Material {
 public:
  explicit SmoothConductor(ConductorFresnel fresnel) : fresnel_(fresnel) {}
  BSDFEval eval(const Vec3&, const Vec3&, TransportMode) const override { return {}; }
  std::optional<BSDFSample> sample(const Vec3& wo, float, Vec2, TransportMode) const override {
    if (wo.z == 0) return std::nullopt;
    Vec3 wi(-wo.x, -wo.y, wo.z);
    return BSDFSample{wi, fresnel_(absCosTheta(wo)) / absCosTheta(wi), 1.f, 1.f, BSDFReflection | BSDFSpecular};
  }
  float pdf(const Vec3&, const Vec3&) const override { return 0; }
  uint32_t flags() const override { return BSDFReflection | BSDFSpecular; }
  std::unique_ptr<Material> mollified(float alpha) const override;
  const ConductorFresnel& fresnel() const { return fresnel_; }  // (specular manifold sampling reads it)

 private:
  ConductorFresnel fresnel_;
};

class RoughConductor final : public Material {
 public:
  RoughConductor(ConductorFresnel fresnel, float alpha, MicrofacetKind kind = MicrofacetKind::GGX,
                 Masking masking = Masking::HeightCorrelated)
      : fresnel_(fresnel), mf_(alpha, kind, masking) {}

  BSDFEval eval(const Vec3& wo, const Vec3& wi, TransportMode) const override {
    if (!sameHemisphere(wo, wi) || wo.z == 0 || wi.z == 0) return {};
    Vec3 wm = wo + wi;
    if (glm::dot(wm, wm) == 0) return {};
    wm = glm::normalize(wm);
    Color f = mf_.D(wm) * fresnel_(absDot(wo, wm)) * mf_.G(wo, wi) / (4 * absCosTheta(wi) * absCosTheta(wo));
    return {f, pdf(wo, wi), pdf(wi, wo)};
  }
  std::optional<BSDFSample> sample(const Vec3& wo, float, Vec2 u, TransportMode mode) const override {
    if (wo.z == 0) return std::nullopt;
    Vec3 woUp = wo.z < 0 ? -wo : wo;  // sample as if from above, then mirror back
    Vec3 wm = mf_.sampleNormal(woUp, u);
    if (glm::dot(woUp, wm) <= 0) return std::nullopt;  // a back-facing normal (Beckmann samples all of D)
    Vec3 wi = reflect(woUp, wm);
    if (wi.z <= 0) return std::nullopt;
    if (wo.z < 0) wi = -wi;
    BSDFEval e = eval(wo, wi, mode);
    if (e.pdf == 0) return std::nullopt;
    return BSDFSample{wi, e.f, e.pdf, e.pdfRev, BSDFReflection | BSDFGlossy};
  }
  float pdf(const Vec3& wo, const Vec3& wi) const override {
    if (!sameHemisphere(wo, wi) || wo.z == 0) return 0;
    Vec3 wm = wo + wi;
    if (glm::dot(wm, wm) == 0) return 0;
    wm = glm::normalize(wm);
    if (wm.z < 0) wm = -wm;
    Vec3 woUp = wo.z < 0 ? -wo : wo;
    return mf_.pdfNormal(woUp, wm) / (4 * absDot(wo, wm));
  }
  uint32_t flags() const override { return BSDFReflection | BSDFGlossy; }

 private:
  ConductorFresnel fresnel_;
  Microfacet mf_;
};

inline std::unique_ptr<Material> SmoothConductor::mollified(float alpha) const {
  auto twin = std::make_unique<RoughConductor>(fresnel_, alpha);
  shareSurfaceWith(*twin);
  return twin;
}

}  // namespace lb
