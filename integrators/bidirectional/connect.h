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
#include "integrators/bidirectional/vertex.h"

namespace lb::bidir {

enum class MisWeighting { Balance, Power, Uniform };

// The techniques that compete for a path in the MIS weights. BDPT: every
// connection. Vertex connection and merging (Georgiev et al. 2012): merging
// at each interior non-delta vertex too, and/or no connections.
struct Techniques {
  bool connections = true;  // every (s, t) with s >= 1 (s = 0, a camera subpath hitting a light, always competes)
  float mergeEta = 0;       // > 0: merging competes, η = (light subpaths per iteration) · π r²
};
struct TechniqueWeights {
  float connection = 0;     // weight of the connection (s, t) itself
  float mergeAtCamera = 0;  // weight of merging light[0..s-1], extended to camera[t-1], at camera[t-1]
};
struct Connection {
  Color L{0.f};          // unweighted contribution
  float weight = 0;      // MIS weight
  Vec2 raster{0.f};      // t = 1: where to splat
  Vertex sampled;        // s = 1: the light point; t = 1: the camera (for tests)
};
// The connection (s, t) and its MIS weight among `techniques` (default:
// BDPT's, every connection and no merging).
Connection connect(const Scene& scene, Sampler& sampler, MisWeighting mis, std::vector<Vertex>& light,
                   std::vector<Vertex>& camera, int sCount, int tCount, uint64_t& rays);
Connection connect(const Scene& scene, Sampler& sampler, MisWeighting mis, const Techniques& techniques,
                   std::vector<Vertex>& light, std::vector<Vertex>& camera, int sCount, int tCount, uint64_t& rays);

// MIS weights of strategy (s, t) and of the merge at camera[t-1]; `sampled`
// replaces y(s-1) when s = 1 and z(t-1) when t = 1. Temporarily edits the
// connection vertices and restores them.
//
// For a merge, `merged` is the light vertex found near camera[t-1], and
// light[0..s-1] its light subpath before it (so light[s-1] may be specular):
// the light subpath's density of camera[t-1] is taken as merged->pdfFwd and
// light[s-2]'s reverse density as cached, since light[s-1] may be a delta
// vertex whose densities cannot be evaluated towards another point
// (Georgiev's report stores the same quantities at the light vertex).
TechniqueWeights techniqueWeights(const Scene& scene, MisWeighting heuristic, const Techniques& allowed,
                                  std::vector<Vertex>& light, std::vector<Vertex>& camera, const Vertex& sampled, int s,
                                  int t, const Vertex* merged = nullptr);
// BDPT's weight: techniqueWeights(..., Techniques{}, ...).connection.
float misWeight(const Scene& scene, MisWeighting heuristic, std::vector<Vertex>& light, std::vector<Vertex>& camera,
                const Vertex& sampled, int s, int t);

}  // namespace lb::bidir
