#pragma once
// Rays and robust spawning. A hit point carries a conservative bound on its
// floating-point error (pError); new rays start just outside that error box,
// along the geometric normal, so they never re-hit the surface they left
// (pbrt-v4 §6.8.6, OffsetRayOrigin). No scene-dependent epsilon anywhere.
#include "core/math.h"

namespace lb {

// Two conventions, one per kind of ray (issue 39):
//  * a ray that looks for the next surface (camera rays, SurfaceInteraction::
//    spawnRay, every scattered direction): d is a unit vector and tMax is ∞
//    (or a distance in world units), so a hit's t is its distance;
//  * a shadow ray between two points (spawnRayTo, a connection): d is the
//    whole segment, not normalised, and tMax is 1 − ShadowEpsilon, so t is a
//    fraction of the segment and the far end's own surface is not hit.
// Embree takes either as it is; only code that reads t as a distance must
// hold a ray of the first kind.
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
