#pragma once
// Auxiliary images of the surfaces seen through each pixel (arbitrary output
// variables), for denoisers and for reading a render: the same for every
// integrator, since they describe the first hit, not the light transport.
//   albedo  the directional albedo of the first hit, ∫ f cos θ dω for the
//           camera's direction, estimated by BSDF sampling (the mean of
//           f cos θ / pdf; a mirror's is its tint, glass's its Fresnel
//           weights); 0 where a ray leaves the scene
//   normal  the shading normal in world space (X, Y, Z), 0 on a miss
//   depth   the distance from the camera along the ray (Z), 0 on a miss (no
//           surface; never Inf in an image)
// Each pixel averages `samples` jittered camera rays (independent random
// numbers from `seed`: the same images at any thread count).
#include "core/image.h"
#include "core/scene.h"

namespace lb {

struct FirstHitImages {
  Image albedo, normal, depth;
};

FirstHitImages renderFirstHitImages(const Scene& scene, int samples, uint64_t seed);

}  // namespace lb
