#pragma once
// Rays and robust spawning. A hit point carries a conservative bound on its
// floating-point error (pError); new rays start just outside that error box,
// along the geometric normal, so they never re-hit the surface they left
// (pbrt-v4 §6.8.6, OffsetRayOrigin). No scene-dependent epsilon anywhere.
#include "core/math.h"

namespace lb {

struct Ray {
  Vec3 o;
  Vec3 d;
  float tMax = Infinity;
};

inline Vec3 offsetRayOrigin(const Vec3& p, const Vec3& pError, const Vec3& ng, const Vec3& w) {
  float dist = glm::dot(glm::abs(ng), pError);
  Vec3 offset = dist * ng;
  if (glm::dot(w, ng) < 0) offset = -offset;
  Vec3 po = p + offset;
  for (int i = 0; i < 3; ++i) {  // round away from p so the offset survives rounding
    if (offset[i] > 0) po[i] = nextFloatUp(po[i]);
    else if (offset[i] < 0) po[i] = nextFloatDown(po[i]);
  }
  return po;
}

// Fraction of a segment's length kept by shadow rays, so the ray stops short of
// the (offset) target point instead of hitting the target's own surface.
constexpr float ShadowEpsilon = 1e-4f;

}  // namespace lb
