#pragma once
// Connecting a light and a camera subpath, and the multiple importance
// sampling weight of the strategy (s, t) that did it (Veach 1997 ch. 10;
// pbrt-v3 §16.3.3–16.3.4). Strategies:
//   s = 0      the camera subpath hits an emitter (or escapes to the environment)
//   s = 1      next-event estimation with a freshly sampled light point
//   t = 1      the light subpath connected to the camera (splatted)
//   otherwise  a deterministic connection of y(s-1) and z(t-1)
#include <vector>
#include "core/sampler.h"
#include "integrators/bidirectional/mis.h"

namespace lb::bidir {

struct Connection {
  Color L{0.f};          // unweighted contribution
  float weight = 0;      // MIS weight
  Vec2 raster{0.f};      // t = 1: where to splat
  Vertex sampled;        // s = 1: the light point; t = 1: the camera (for tests)
};
// The connection (s, t) and its MIS weight among `techniques` (default:
// BDPT's, every connection and no merging).
// Both subpaths carry partial sums (mis.h) for `techniques` and `mis`.
Connection connect(const Scene& scene, Sampler& sampler, MisWeighting mis, Subpath light,
                   Subpath camera, int sCount, int tCount, uint64_t& rays);
Connection connect(const Scene& scene, Sampler& sampler, MisWeighting mis, const Techniques& techniques,
                   Subpath light, Subpath camera, int sCount, int tCount,
                   uint64_t& rays);

// BDPT's weight: techniqueWeights(..., Techniques{}, ...).connection.
// (Both subpaths carry partial sums for Techniques{} and this heuristic.)
float misWeight(const Scene& scene, MisWeighting heuristic, Subpath light,
                Subpath camera, const Vertex& sampled, int s, int t);

}  // namespace lb::bidir
