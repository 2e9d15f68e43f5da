#pragma once
// Dielectrics: smooth glass (delta reflection + refraction, Fresnel-weighted
// choice, total internal reflection) and rough GGX glass (Walter et al. 2007,
// as formulated in pbrt-v4 §9.7). `eta` is the interior IOR over the exterior.
#include "core/bsdfs/fresnel.h"
#include "core/bsdfs/material.h"
#include "core/bsdfs/microfacet.h"

namespace lb {

class SmoothDielectric final : public Material {
 public:
  explicit SmoothDielectric(float eta) : eta_(eta) {}
  BSDFEval eval(const Vec3&, const Vec3&, TransportMode) const override { return {}; }
  std::optional<BSDFSample> sample(const Vec3& wo, float uLobe, Vec2, TransportMode mode) const override;
  float pdf(const Vec3&, const Vec3&) const override { return 0; }
  uint32_t flags() const override { return BSDFReflection | BSDFTransmission | BSDFSpecular; }
  float relativeEta(const Vec3& wo) const override { return wo.z > 0 ? eta_ : 1 / eta_; }
  std::unique_ptr<Material> mollified(float alpha) const override;
  float eta() const { return eta_; }  // interior over exterior (manifold next-event estimation reads it)

 private:
  float eta_;
};

class RoughDielectric final : public Material {
 public:
  RoughDielectric(float eta, float alpha, MicrofacetKind kind = MicrofacetKind::GGX,
                  Masking masking = Masking::HeightCorrelated)
      : eta_(eta), mf_(alpha, kind, masking) {}
  BSDFEval eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const override;
  std::optional<BSDFSample> sample(const Vec3& wo, float uLobe, Vec2 u, TransportMode mode) const override;
  float pdf(const Vec3& wo, const Vec3& wi) const override;
  // pdf() without the Fresnel choice of reflection or refraction: the density
  // of wi when sample() is told which of the two to take (a layered BSDF's
  // walk, core/bsdfs/layered.h).
  float lobePdf(const Vec3& wo, const Vec3& wi) const;
  uint32_t flags() const override { return BSDFReflection | BSDFTransmission | BSDFGlossy; }
  float relativeEta(const Vec3& wo) const override { return wo.z > 0 ? eta_ : 1 / eta_; }

 private:
  // The generalised half vector of (wo, wi), facing +z; false if degenerate or
  // either direction meets a back-facing microfacet.
  bool halfVector(const Vec3& wo, const Vec3& wi, Vec3* wm, float* etap) const;
  float eta_;
  Microfacet mf_;
};

}  // namespace lb
