#pragma once
// The BSDF at a hit point, in world space: a material plus the shading frame.
// One place handles, for every material:
//  * light leaks: a direction whose side of the shading normal disagrees with
//    its side of the geometric normal scatters nothing (both modes alike, so
//    adjoint estimators still agree);
//  * the adjoint shading-normal correction for importance transport (Veach 1997,
//    §5.3, Eq. 5.19): f*·|wo·ns||wi·ng| / (|wo·ng||wi·ns|), so integrators keep
//    multiplying by |wi·ns| in both modes;
//  * the material's texture at the hit's uv (material.h).
#include "core/bsdfs/material.h"
#include "core/interaction.h"
#include "core/sampling.h"

namespace lb {

// A sampled scattering direction in world space. `weight` = f·|cos θ_wi|/pdf is
// computed in the shading frame, before the direction leaves it.
struct ScatterSample {
  Vec3 wi;
  Color f{0.f};
  Color weight{0.f};
  float pdf = 0, pdfRev = 0;
  uint32_t lobe = 0;
  float eta = 1;
  bool isDelta() const { return lobe & BSDFSpecular; }
};

class BSDF {
 public:
  BSDF(const SurfaceInteraction& si)
      : frame_(si.shading), ng_(si.ng), material_(si.material), texture_(si.material->textureAt(si.uv)) {}
  // With `material` in place of the hit's (a regularized twin, material.h's mollified()).
  BSDF(const SurfaceInteraction& si, const Material* material)
      : frame_(si.shading), ng_(si.ng), material_(material), texture_(material->textureAt(si.uv)) {}

  const Material& material() const { return *material_; }
  bool isDelta() const { return material_->isDelta(); }
  uint32_t flags() const { return material_->flags(); }
  const Frame& frame() const { return frame_; }
  const Vec3& shadingNormal() const { return frame_.n; }

  BSDFEval eval(const Vec3& woWorld, const Vec3& wiWorld, TransportMode mode) const {
    Vec3 wo = frame_.toLocal(woWorld), wi = frame_.toLocal(wiWorld);
    if (leaks(woWorld, wo) || leaks(wiWorld, wi)) return {};
    BSDFEval e = material_->evalTextured(wo, wi, mode, texture_);
    e.f *= adjointCorrection(woWorld, wiWorld, wo, wi, mode);
    return e;
  }

  std::optional<ScatterSample> sample(const Vec3& woWorld, float uLobe, Vec2 u, TransportMode mode) const {
    Vec3 wo = frame_.toLocal(woWorld);
    if (wo.z == 0 || leaks(woWorld, wo)) return std::nullopt;
    auto s = material_->sampleTextured(wo, uLobe, u, mode, texture_);
    if (!s || s->pdf == 0) return std::nullopt;
    Vec3 wiWorld = frame_.toWorld(s->wi);
    if (leaks(wiWorld, s->wi)) return std::nullopt;
    Color f = s->f * adjointCorrection(woWorld, wiWorld, wo, s->wi, mode);
    return ScatterSample{wiWorld, f, f * absCosTheta(s->wi) / s->pdf, s->pdf, s->pdfRev, s->lobe, s->eta};
  }

  // The albedo of this hit, defined once for AOVs, denoising and any
  // integrator that wants one (issue 39): a one-sample estimate of the
  // directional albedo ρ(wo) = ∫ f(wo, wi) |cos θi| dωi, the weight
  // f·|cos θ|/pdf of one BSDF sample (black if the sample fails). Its mean is
  // ρ(wo), which includes transmission and a delta lobe's Fresnel weight.
  Color albedoSample(const Vec3& woWorld, float uLobe, Vec2 u) const {
    auto s = sample(woWorld, uLobe, u, TransportMode::Radiance);
    return s ? s->weight : Color(0.f);
  }

  // "The hemisphere" of a surface for an integrator that samples one
  // (ambient occlusion, gathering), defined once (issue 39): a cosine-weighted
  // direction on wo's side of the shading normal, with its density
  // |cos θ|/π per solid angle. nullopt where wo or that direction would leak:
  // lie on the other side of the geometric normal than of the shading normal
  // (see leaks above; with interpolated normals near a silhouette), as
  // sample(), eval() and pdf() refuse them.
  struct HemisphereSample {
    Vec3 wi;
    float pdf;
  };
  std::optional<HemisphereSample> sampleCosineOnWoSide(const Vec3& woWorld, Vec2 u) const {
    Vec3 wo = frame_.toLocal(woWorld);
    if (wo.z == 0 || leaks(woWorld, wo)) return std::nullopt;
    Vec3 local = sampleCosineHemisphere(u);
    if (wo.z < 0) local.z = -local.z;
    Vec3 wi = frame_.toWorld(local);
    if (local.z == 0 || leaks(wi, local)) return std::nullopt;
    return HemisphereSample{wi, std::abs(local.z) * InvPi};
  }

  float pdf(const Vec3& woWorld, const Vec3& wiWorld) const {
    Vec3 wo = frame_.toLocal(woWorld), wi = frame_.toLocal(wiWorld);
    if (leaks(woWorld, wo) || leaks(wiWorld, wi)) return 0;
    return material_->pdf(wo, wi);
  }

 private:
  bool leaks(const Vec3& world, const Vec3& local) const { return glm::dot(world, ng_) * local.z <= 0; }
  float adjointCorrection(const Vec3& woW, const Vec3& wiW, const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    if (mode == TransportMode::Radiance) return 1.f;
    float num = std::abs(wo.z) * absDot(wiW, ng_);
    float den = absDot(woW, ng_) * std::abs(wi.z);
    return den > 0 ? num / den : 0.f;
  }

  Frame frame_;
  Vec3 ng_;
  const Material* material_;
  Color texture_;  // the material's texture at this hit (1 if it has none)
};

}  // namespace lb
