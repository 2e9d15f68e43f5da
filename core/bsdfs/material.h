#pragma once
// Conventions, fixed once for every BSDF (the renderers we learn from disagree):
//  * Directions are in the local shading frame (normal = +z) and both point AWAY
//    from the surface.
//  * `wo` points to the vertex the path came from (the camera side when tracing
//    radiance, the light side when tracing importance); `wi` is the direction
//    being sampled or connected to, i.e. where the path goes next.
//  * f(wo, wi) excludes the cosine. Integrators multiply by |cos θ_wi| taken
//    against the shading normal, in both transport modes.
//  * `pdf` is the solid-angle density of sampling wi given wo; `pdfRev` that of
//    sampling wo given wi (what bidirectional MIS needs).
//  * Delta (specular) lobes return f = 0 from eval; sample() returns f as the
//    value to multiply by |cos θ_wi| / pdf, and pdf as the discrete probability
//    of the chosen lobe.
//  * In TransportMode::Importance, refraction does not scale by 1/η² (radiance
//    does; Veach 1997 §5.2). The shading-normal adjoint correction is applied
//    by the BSDF wrapper (bsdf.h), never by a material.
//  * A material may carry a texture (core/textures/texture.h), evaluated at
//    the hit's uv by the BSDF wrapper and passed to evalTextured() and
//    sampleTextured(). By default f is scaled by it (diffuse albedo, conductor
//    tint); a material where only one lobe is textured (plastic: its diffuse
//    base) overrides both. Either way pdfs and sampling do not depend on the
//    texture's value at the hit, so pdf() needs no uv.
#include <memory>
#include <optional>
#include <string>
#include "core/frame.h"
#include "core/textures/texture.h"

namespace lb {

enum class TransportMode { Radiance, Importance };

enum BSDFFlags : uint32_t {
  BSDFReflection = 1,
  BSDFTransmission = 2,
  BSDFDiffuse = 4,
  BSDFGlossy = 8,
  BSDFSpecular = 16,
};

struct BSDFEval {
  Color f{0.f};
  float pdf = 0;
  float pdfRev = 0;
};

struct BSDFSample {
  Vec3 wi;
  Color f{0.f};
  float pdf = 0;
  float pdfRev = 0;
  uint32_t lobe = 0;  // BSDFFlags of the sampled lobe
  float eta = 1;      // relative IOR crossed (1 for reflection)
  bool isDelta() const { return lobe & BSDFSpecular; }
  Color weight() const { return pdf > 0 ? f * absCosTheta(wi) / pdf : Color(0.f); }
};

class Material {
 public:
  virtual ~Material() = default;
  virtual BSDFEval eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const = 0;
  // uLobe chooses between lobes (e.g. reflect vs refract); u drives the direction.
  virtual std::optional<BSDFSample> sample(const Vec3& wo, float uLobe, Vec2 u, TransportMode mode) const = 0;
  virtual float pdf(const Vec3& wo, const Vec3& wi) const = 0;
  virtual uint32_t flags() const = 0;

  // eval() and sample() with the texture's value at the hit (1 where there is
  // no texture). By default it is a factor on f.
  virtual BSDFEval evalTextured(const Vec3& wo, const Vec3& wi, TransportMode mode, const Color& texture) const {
    BSDFEval e = eval(wo, wi, mode);
    e.f *= texture;
    return e;
  }
  virtual std::optional<BSDFSample> sampleTextured(const Vec3& wo, float uLobe, Vec2 u, TransportMode mode,
                                                   const Color& texture) const {
    auto s = sample(wo, uLobe, u, mode);
    if (s) s->f *= texture;
    return s;
  }

  // Whether pdf() (and the pdf sample() reports) is the true density of
  // sample()'s directions. Layered materials estimate it (layered.h): MIS
  // weights that only need to sum to 1 do not mind, an estimator that
  // integrates the density itself (optimal MIS's control variates) does.
  virtual bool exactDensity() const { return true; }

  // Relative IOR crossed when transmitting from wo's side (1 for opaque materials).
  virtual float relativeEta(const Vec3& /*wo*/) const { return 1.f; }

  // Surface maps (core/textures/surface_maps.h): a tangent-space normal map
  // or a bump map replaces the shading normal, an opacity below 1 lets rays
  // pass the surface. Both are applied where hits are found (Scene), so
  // every integrator, shadow ray and light subpath sees them alike; BSDFs
  // never do.
  struct SurfaceMaps {
    std::shared_ptr<const Texture> normal, bump, opacity;
    float bumpScale = 1;
  };
  void setSurfaceMaps(SurfaceMaps maps) { maps_ = std::move(maps); }
  const SurfaceMaps& surfaceMaps() const { return maps_; }
  bool perturbsShading() const { return maps_.normal || maps_.bump; }

  void setTexture(std::shared_ptr<const Texture> t) { texture_ = std::move(t); }
  Color textureAt(Vec2 uv) const { return texture_ ? texture_->eval(uv) : Color(1.f); }
  const Texture* texture() const { return texture_.get(); }

  bool isDelta() const { return (flags() & BSDFSpecular) && !(flags() & (BSDFDiffuse | BSDFGlossy)); }
  bool hasTransmission() const { return flags() & BSDFTransmission; }

  // Path-space regularization (Kaplanyan & Dachsbacher 2013): this delta
  // material mollified into a rough twin, a GGX lobe of width `alpha` about
  // each of its specular directions (same IOR or Fresnel, texture and
  // surface maps); null for materials without one (non-delta ones, and thin
  // dielectrics, whose rough form would be a different slab).
  virtual std::unique_ptr<Material> mollified(float /*alpha*/) const { return nullptr; }

 protected:
  // The texture and surface maps, shared with a twin (mollified()).
  void shareSurfaceWith(Material& twin) const {
    twin.texture_ = texture_;
    twin.maps_ = maps_;
  }

 private:
  std::shared_ptr<const Texture> texture_;
  SurfaceMaps maps_;
};

// A material whose texture is not a factor on f (plastic's scales its
// diffuse base only; a layered BSDF's, its base): it implements the textured
// forms, and eval() and sample() are them with a texture of 1.
class LobeTexturedMaterial : public Material {
 public:
  BSDFEval eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const final {
    return evalTextured(wo, wi, mode, Color(1.f));
  }
  std::optional<BSDFSample> sample(const Vec3& wo, float uLobe, Vec2 u, TransportMode mode) const final {
    return sampleTextured(wo, uLobe, u, mode, Color(1.f));
  }
  BSDFEval evalTextured(const Vec3& wo, const Vec3& wi, TransportMode mode, const Color& texture) const override = 0;
  std::optional<BSDFSample> sampleTextured(const Vec3& wo, float uLobe, Vec2 u, TransportMode mode,
                                           const Color& texture) const override = 0;
};

}  // namespace lb
