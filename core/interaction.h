#pragma once
// A point on a surface as the integrators see it. `ng` is the geometric normal
// (from the triangle winding or the sphere, flipped to agree with the shading
// normal where a mesh supplies one); `shading.n` is the interpolated normal.
#include "core/frame.h"
#include "core/ray.h"

namespace lb {

class Material;
class Light;

struct SurfaceInteraction {
  Vec3 p;
  Vec3 pError;  // conservative absolute error bound of p, per axis
  Vec3 ng;
  Frame shading;
  Vec2 uv{0, 0};
  // ∂p/∂u and ∂p/∂v of the surface's uv parametrisation: filled only where a
  // material's normal or bump map needs them (Shape::surfaceTangents).
  Vec3 dpdu{0.f}, dpdv{0.f};
  Vec3 wo;      // unit direction back along the incoming ray
  float t = 0;  // ray distance
  const Material* material = nullptr;
  const Light* emitter = nullptr;  // the area light on this shape, if any
  int shapeId = -1;
  int primId = -1;

  Ray spawnRay(const Vec3& d) const { return {offsetRayOrigin(p, pError, ng, d), d, Infinity}; }
  // Shadow ray towards another surface point (both ends offset) or, with zero
  // error and normal, towards a point light.
  Ray spawnRayTo(const Vec3& target, const Vec3& targetError, const Vec3& targetNormal) const {
    Vec3 from = offsetRayOrigin(p, pError, ng, target - p);
    Vec3 to = offsetRayOrigin(target, targetError, targetNormal, from - target);
    return {from, to - from, 1 - ShadowEpsilon};
  }
};

}  // namespace lb
