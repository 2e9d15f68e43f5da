#pragma once
// Bidirectional path tracing (Veach 1997 ch. 10; Veach & Guibas 1995). Each
// sample builds a camera subpath z0…z(t-1) and a light subpath y0…y(s-1), both
// with Russian roulette, and evaluates every connection strategy (s, t):
//   s = 0      the camera subpath hits an emitter (or escapes to the environment)
//   s = 1      next-event estimation with a freshly sampled light point
//   t = 1      the light subpath connected to the camera and splatted
//   otherwise  a deterministic connection of y(s-1) and z(t-1)
// weighted by multiple importance sampling over all strategies that could have
// produced the same path, computed in time linear in its length by the
// pdf-ratio recursion (pbrt-v3 §16.3.4, MISWeight).
//
//   max_depth, rr, rr_depth  path length in segments and roulette on both
//                            subpaths (path_length.h), as in `path` and `light`
//   mis              power   power (β = 2) | balance | uniform (1 / number of strategies)
//   strategy_images  0       write weighted and unweighted images of every (s, t)
//                            with s + t - 1 <= this length (0: none)
#include <memory>
#include <vector>
#include "core/params.h"
#include "integrators/path_length.h"
#include "integrators/bdpt/vertex.h"
#include "integrators/integrator.h"

namespace lb {

enum class MisWeighting { Balance, Power, Uniform };

struct BdptSettings {
  PathLength length;
  MisWeighting mis = MisWeighting::Power;
  int strategyImages = 0;
  static BdptSettings read(Params& p);
};

namespace bdpt {

// Random walks. `maxVertices` bounds the vertices added after the start.
int generateCameraSubpath(const Scene& scene, Sampler& sampler, const BdptSettings& s, Vec2 raster,
                          std::vector<Vertex>& path, uint64_t& rays);
int generateLightSubpath(const Scene& scene, Sampler& sampler, const BdptSettings& s, std::vector<Vertex>& path,
                         uint64_t& rays);

struct Connection {
  Color L{0.f};          // unweighted contribution
  float weight = 0;      // MIS weight
  Vec2 raster{0.f};      // t = 1: where to splat
  Vertex sampled;        // s = 1: the light point; t = 1: the camera (for tests)
};
Connection connect(const Scene& scene, Sampler& sampler, const BdptSettings& s, std::vector<Vertex>& light,
                   std::vector<Vertex>& camera, int sCount, int tCount, uint64_t& rays);

// MIS weight of strategy (s, t); `sampled` replaces y(s-1) when s = 1 and
// z(t-1) when t = 1. Temporarily edits the connection vertices and restores them.
float misWeight(const Scene& scene, MisWeighting heuristic, std::vector<Vertex>& light, std::vector<Vertex>& camera,
                const Vertex& sampled, int s, int t);

}  // namespace bdpt

class Bdpt final : public Integrator {
 public:
  explicit Bdpt(BdptSettings s) : settings_(s) {}
  void renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass, PassStats& stats) override;
  std::vector<std::string> writeExtraOutputs(const std::string& stem) const override;
  // Per-strategy film (after a render with strategy_images > 0), or null.
  const Film* strategyFilm(int s, int t, bool weighted) const {
    int k = strategyIndex(s, t);
    return k < 0 ? nullptr : (weighted ? weighted_ : unweighted_)[size_t(k)].get();
  }

 private:
  BdptSettings settings_;
  // Per-strategy films (weighted, unweighted), index strategyIndex(s, t).
  std::vector<std::unique_ptr<Film>> weighted_, unweighted_;
  std::vector<std::pair<int, int>> strategies_;
  int strategyIndex(int s, int t) const;
};

}  // namespace lb
