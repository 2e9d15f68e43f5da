#pragma once
// A learned distribution of directions at a path vertex, sampled as one
// component of a one-sample mixture with the BSDF (path guiding: Dahm & Keller
// 2017; Müller, Gross, Novák 2017, §4). The path estimator asks for it at
// every vertex when the `guided` integrator gives one (PathContext::guide):
//
//   p(ω) = c · p_bsdf(ω) + (1 − c) · p_guide(ω),    c = bsdf_fraction ∈ (0, 1]
//
// Every direction is weighted f·|cos θ| / p(ω) with this p evaluated exactly,
// whichever component drew it, and next-event estimation weighs its light
// samples by MIS against the same p (Veach 1997, Eq. 9.13). Because c > 0, a
// direction the BSDF can sample keeps p > 0 even where the guide has none: a
// region the guide never learned is never excluded, so the estimator stays
// unbiased whatever was learned — provided the guide is fixed while it is
// used (the integrator learns only between passes).
//
// One object per thread: prepare() looks the distribution up for one vertex
// (and may cache per-vertex data); pdf() and sample() then refer to it.
#include "core/bsdfs/bsdf.h"
#include "core/interaction.h"

namespace lb {

class DirectionGuide {
 public:
  explicit DirectionGuide(float bsdfFraction) : bsdfFraction_(bsdfFraction) {}
  virtual ~DirectionGuide() = default;

  // Looks up the distribution at `si`. False where the vertex is not guided:
  // BSDFs with a delta lobe (a mixture with a delta distribution has no
  // density to evaluate), or nothing learned there yet; the BSDF alone is
  // sampled then.
  bool prepare(const SurfaceInteraction& si, const BSDF& bsdf) {
    active_ = !(bsdf.flags() & BSDFSpecular) && prepareAt(si, bsdf);
    return active_;
  }
  bool active() const { return active_; }
  float bsdfFraction() const { return bsdfFraction_; }

  // The guiding component's solid-angle density, and a direction drawn from
  // it with that density (computed on the way, saving a second look-up).
  virtual float pdf(const Vec3& wi) const = 0;
  virtual Vec3 sample(Vec2 u, float* pdf) const = 0;
  // The mixture's density, given the BSDF's density of the same direction.
  float mixturePdf(float bsdfPdf, const Vec3& wi) const {
    return bsdfFraction_ * bsdfPdf + (1 - bsdfFraction_) * pdf(wi);
  }

 protected:
  virtual bool prepareAt(const SurfaceInteraction& si, const BSDF& bsdf) = 0;

 private:
  float bsdfFraction_;
  bool active_ = false;
};

}  // namespace lb
