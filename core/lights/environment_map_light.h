#pragma once
// An HDR environment map: radiance arriving from direction d is the texel of
// a latitude-longitude image at u = φ / 2π, v = θ / π, with θ measured from
// +y (v = 0 is straight up) and d = (sin θ sin φ, cos θ, −sin θ cos φ) before
// the map's rotation (u = 0 looks along −z; Mitsuba's envmap convention). Each texel is constant
// (nearest lookup), so that importance sampling below follows Le exactly.
//
// Importance sampling (pbrt-v3 §14.2.4, pbrt-v4 §12.5.2): a piecewise-
// constant 2-D distribution over texels, weights max(r, g, b) × sin θ at the
// texel's centre; a row from the marginal, a column from that row's
// conditional, each inverted by binary search (DiscreteDistribution). The
// density over (u, v) becomes one over directions through the lat-long
// mapping's Jacobian: p(ω) = p(u, v) / (2π² sin θ). `uniform` sampling (over
// the sphere) is kept to measure what importance sampling gains.
//
// MIS compensation (Karlík et al. 2019, as pbrt-v4's image infinite light):
// a second distribution with weights max(0, m − m̄) × sin θ, m = max(r, g, b)
// of a texel and m̄ its mean over the sphere, for path tracing's NEE under
// MIS with BSDF sampling (sampleLiCompensated/pdfLiCompensated). A map with
// no texel above its mean (a constant one) keeps the full distribution.
//
// Both directions, as every light: sampleLi/pdfLi for next-event estimation,
// sampleLe/pdfLe (a direction from the same distribution, a point on a disc
// covering the scene) for light tracing, BDPT, VCM and the photon methods.
#include <mutex>
#include <vector>
#include "core/image.h"
#include "core/lights/light.h"
#include "core/sampling.h"

namespace lb {

class EnvironmentMapLight final : public Light {
 public:
  // `toWorld` turns the map's frame into the world's: a rotation (or any
  // orthogonal matrix), Mitsuba's to_world.
  EnvironmentMapLight(Image map, float scale, const Mat3& toWorld, bool importance);

  void preprocess(const Bounds3& b) override;
  std::optional<LightSample> sampleLi(const Vec3& ref, float uPick, Vec2 u) const override;
  float pdfLi(const Vec3& ref, const Vec3& wi, const Vec3& pLight, const Vec3& nLight) const override;
  std::optional<LightSample> sampleLiCompensated(const Vec3& ref, float uPick, Vec2 u) const override;
  float pdfLiCompensated(const Vec3& ref, const Vec3& wi, const Vec3& pLight, const Vec3& nLight) const override;
  std::optional<LightEmission> sampleLe(float uPick, Vec2 uPos, Vec2 uDir) const override;
  void pdfLe(const Vec3& p, const Vec3& n, const Vec3& dir, float* pdfPos, float* pdfDir) const override;
  Color power() const override;
  Color Le(const Vec3& d) const override;
  bool isDelta() const override { return false; }
  bool isInfinite() const override { return true; }

  // ∫ Le dω over the sphere, summed texel by texel (exact for this map).
  Color integral() const;
  // Solid-angle density of the direction sampler (importance or uniform;
  // `compensated`: the MIS-compensated one).
  float directionPdf(const Vec3& d, bool compensated = false) const;

 private:
  // Texels drawn by a row from the marginal, then a column from that row's conditional.
  struct TexelDistribution {
    DiscreteDistribution rows;
    std::vector<DiscreteDistribution> columns;
  };
  // Weights w(x, y) for every texel, m(x, y) × sin θ as above (m relative to the brightest texel).
  template <typename Weight>
  TexelDistribution texelDistribution(Weight&& w) const;
  const TexelDistribution& distribution(bool compensated) const;
  double relativeMax(int x, int y) const;  // max(r, g, b) of a texel over the brightest texel's
  // A direction towards the environment, and its solid-angle pdf (0: none).
  Vec3 sampleDirection(Vec2 u, float* pdf, bool compensated = false) const;
  // sampleLi and sampleLiCompensated: a point beyond the scene in a sampled direction.
  std::optional<LightSample> sampleLiFrom(const Vec3& ref, Vec2 u, bool compensated) const;
  Vec2 uvOf(const Vec3& worldDir) const;
  Vec3 directionOf(Vec2 uv) const;
  const Color& texel(Vec2 uv) const;

  Image map_;
  float scale_;
  Mat3 toWorld_, toMap_;
  bool importance_;
  double unit_ = 1;                  // 1 / the brightest texel's max(r, g, b)
  std::vector<double> rowSinTheta_;  // sin θ at each row's centre
  TexelDistribution full_;
  mutable std::once_flag compensatedOnce_;
  mutable TexelDistribution compensated_;
  mutable bool compensatedIsFull_ = false;
  Vec3 center_{0.f};
  float radius_ = 1;
};

}  // namespace lb
