#pragma once
// Spatial light selection: which light to sample for next-event estimation
// depends on where the shading point is. A preprocess lays a grid of up to
// 16³ voxels over the scene's bounds and, for each voxel, a distribution over
// the lights in proportion to an estimate of each light's contribution there
// (the "per-voxel table" variant of the light-selection schemes that pbrt-v4's
// BVH light sampler and Conty & Kulla 2018's light tree refine):
//
//   estimate(l, g) = mean over 8 samples of luminance(L) / pdf   from sampleLi at grid vertex g
//                  = the light's fluence ∫ L dω at g, without visibility or the BSDF
//   s_v(l)         = max of estimate(l, g) over the voxel's 8 corner vertices
//   pmf_v(l)       = (1 − ε) · s_v(l) / Σ_l' s_v(l') + ε · pmf_scene(l),   ε = 0.1
//
// The maximum over corners keeps a light that is bright anywhere in the voxel
// (a one-sided light whose plane cuts the voxel); the defensive mixture with
// the scene's own selection (Hesterberg 1995) keeps every emitting light's
// probability positive everywhere, so the estimator stays unbiased whatever
// the table misses (occluders, which it ignores). Points outside the bounds
// use the nearest voxel.
#include <vector>
#include "core/scene.h"

namespace lb {

class SpatialLightSampler {
 public:
  SpatialLightSampler(const Scene& scene, uint64_t seed);
  const Light* sample(const Vec3& p, float u, float* pmf) const;
  float pmf(const Vec3& p, const Light* light) const;
  int resolution() const { return res_; }

  static constexpr float DefensiveFraction = 0.1f;

 private:
  size_t voxelOf(const Vec3& p) const;
  const std::vector<std::unique_ptr<Light>>* lights_ = nullptr;
  Bounds3 bounds_;
  Vec3 extent_{1.f};
  int res_ = 1;
  std::vector<DiscreteDistribution> voxels_;
};

}  // namespace lb
