#pragma once
// Photon paths: a light chosen by power, an emitted ray, importance-mode BSDF
// sampling, Russian roulette by the scattering weight (Jensen's "albedo"
// roulette: photons keep roughly constant power). At every non-specular hit
// the visitor receives the photon; paths are traced in fixed-size chunks in
// parallel, and the visitor is told the chunk, so callers can merge results
// in chunk order: deterministic for a fixed seed whatever the thread count.
#include <cstdint>
#include <functional>
#include "core/progress.h"
#include <optional>
#include "core/sampler.h"
#include "core/interaction.h"
#include "core/scene.h"

namespace lb {

struct PhotonHit {
  const SurfaceInteraction* si;
  Vec3 wi;              // towards where the photon came from
  Color beta;           // flux of this photon path, not yet divided by the number of paths
  int bounces;          // surface interactions before this one (0: straight from the light);
                        // the photon has travelled bounces + 1 segments
  bool specularChain;   // every earlier bounce was specular (and there was at least one): L S+ here
};

constexpr size_t PhotonPathsPerChunk = 4096;

// The camera side shared by photon mapping and SPPM: follow a camera ray
// through specular (delta) bounces to the first non-specular surface,
// collecting emission seen directly or through those bounces, over at most
// `maxDepth` segments.
struct NonSpecularHit {
  Color emitted{0.f};                     // radiance reached along the way
  Color beta{1.f};                        // throughput of the specular chain
  float firstHitDistance = Infinity;      // of the ray's first surface (infinity if it escaped)
  std::optional<SurfaceInteraction> si;   // the surface, if one was reached
  int segments = 0;                       // segments from the ray's origin to si
};
NonSpecularHit traceToNonSpecular(const Scene& scene, Ray ray, Sampler& sampler, int maxDepth, uint64_t& rays);

// Calls visit(chunk, hit) for each non-specular hit of `paths` photon paths
// (path i uses random numbers seeded by (seed, i, pass)). Returns the number
// of rays traced. maxBounces bounds the surface interactions per path, so
// photons travel at most maxBounces segments.
// `progress`, if given, advances by one per path. With `specularChainsOnly`
// a path ends once its chain of delta bounces breaks: a caustic map stores
// nothing after that, and the paths' random numbers are their own, so the
// photons it keeps are the same.
uint64_t tracePhotons(const Scene& scene, uint64_t seed, uint64_t pass, size_t paths, int maxBounces,
                      const std::function<void(size_t chunk, const PhotonHit&)>& visit, Progress* progress = nullptr,
                      bool specularChainsOnly = false);

}  // namespace lb
