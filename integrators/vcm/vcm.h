#pragma once
// Vertex connection and merging (Georgiev, Křivánek, Davidovič, Slusallek
// 2012; Hachisuka, Pantaleoni, Jensen 2012 "unified path sampling"), after
// SmallVCM. Each pass (an "iteration"):
//  1. one light subpath per pixel (N = width × height of them); with
//     connections on, each is connected to the camera (t = 1) and splatted;
//  2. the light subpaths' non-specular surface vertices (not the light's
//     own) are indexed for range search at the iteration's radius
//        r_i = r_1 · i^((α−1)/2),   i = 1, 2, …
//     (Georgiev et al. §5: the variance of a merge grows as r shrinks, its
//     bias falls; α in (0, 1] trades the two, α = 1 keeps r fixed);
//  3. one camera subpath per pixel; at each of its vertices it is connected
//     to its pixel's light subpath (every BDPT strategy: s = 0 hitting a
//     light, s = 1 next-event estimation, s ≥ 2 a vertex connection) and
//     merged with every indexed light vertex within r, a merge adding
//        β_camera · f(ω_camera, ω_light) · β_light / (N π r²) · |ω·n_s|/|ω·n_g|;
//  4. every contribution is weighted by MIS over all connections and merges
//     that could have produced its path (integrators/bidirectional/connect.h:
//     pbrt's ratio walk extended with merges, η = N π r²).
// Modes (SmallVCM's algorithms, comparable in one experiment):
//   vcm  connections and merging
//   bpm  bidirectional photon mapping: merging at every camera vertex, and
//        camera subpaths hitting lights; no connections
//   ppm  progressive photon mapping: camera subpaths through specular
//        vertices to the first non-specular one, merged there (weight 1);
//        lights seen through specular chains count directly
//   bpt  connections only: bidirectional path tracing, the same estimator as
//        `bdpt` (one light subpath per pixel per pass)
//   lvc  the light-vertex-cache BDPT (Davidovič, Křivánek, Hašan & Slusallek
//        2014; SeeSharp's VertexCacheBidir): as bpt, but each camera vertex
//        connects to `connections` (k) vertices drawn uniformly from all M
//        connectible light vertices of the pass (the light's own excluded)
//        instead of its own light subpath's, so the number of connections no
//        longer grows with the light subpath's length. A draw's contribution
//        is divided by its expected count k·N/M (N light subpaths); the MIS
//        weights count it the same way (bidir::Techniques::connectionCount),
//        with the M of the previous pass (the first: N), so they do not
//        depend on this pass's light subpaths and the estimator is unbiased.
//        The cached light vertices are ordered by tile, so the draws and the
//        image do not depend on the thread count.
//
//   mode             vcm
//   connections      1       lvc: light vertices each camera vertex connects to
//   max_depth, rr, rr_depth  path length in segments, roulette (path_length.h)
//   mis              power   power | balance
//   radius           0       r_1 in world units; 0: relative_radius × the scene's bounding radius
//   relative_radius  0.003   (SmallVCM's default)
//   alpha            0.75    radius reduction, in (0, 1]
//   lookup           grid    grid | flann: the merging range search, a hashed
//                            uniform grid of cell size 2r built in parallel
//                            (photon_map/hash_grid.h, as SmallVCM) or FLANN's
//                            kd-tree; the same merges in the same order either
//                            way (a test checks the images are identical). The
//                            grid is the faster: its build took 1.2–1.5 ms per
//                            iteration against FLANN's 7 ms (serial), on the
//                            Cornell box with spheres at 128² (docs/results.md,
//                            `lightbench_bench --benchmark_filter=VcmIteration`).
//   regularize       false   path-space regularization (core/bsdfs/regularization.h),
//                            as in bdpt: both subpaths' walks follow the path rule,
//                            merges happen at camera vertices only, so a merge at a
//                            rough twin is one the rule allows; regularize_roughness
//                            α_0 (0.1) shrinking as (k + 1)^-regularize_exponent (1/6)
#include <memory>
#include <vector>
#include "core/bsdfs/regularization.h"
#include "core/params.h"
#include "integrators/bidirectional/connect.h"
#include "integrators/integrator.h"
#include "integrators/path_length.h"

namespace lb {

enum class VcmMode { Vcm, Bpm, Ppm, Bpt, Lvc };

struct VcmSettings {
  VcmMode mode = VcmMode::Vcm;
  PathLength length;
  bidir::MisWeighting mis = bidir::MisWeighting::Power;
  float radius = 0, relativeRadius = 0.003f;
  float alpha = 0.75f;
  bool gridLookup = true;
  int cacheConnections = 1;  // lvc: k
  RegularizationSettings regularization;
  // lvc, for tests only (no key): the count the weights give a connection
  // instead of k·N/M; 0: k·N/M. Any count keeps the estimator unbiased (the
  // weights still sum to 1), so a test can give connections nearly all the
  // weight and see their contributions alone.
  double weightCountOverride = 0;
  static VcmSettings read(Params& p);
  bool connections() const { return mode == VcmMode::Vcm || mode == VcmMode::Bpt || mode == VcmMode::Lvc; }
  bool merging() const { return mode != VcmMode::Bpt && mode != VcmMode::Lvc; }
};

class Vcm final : public Integrator {
 public:
  explicit Vcm(VcmSettings s);
  // mode bpt merges nothing and is unbiased; merging shrinks its radius with
  // the pass index, which a chunk would restart (the bias of its own passes),
  // and so does regularization its roughness.
  std::string splitRefusal() const override {
    if (settings_.merging())
      return "its merging radius shrinks with the pass index; a chunk restarts it, so the mean "
             "of chunks keeps the bias of one chunk's passes (modes bpt and lvc, unbiased, split exactly)";
    return settings_.regularization.enabled ? "regularize: its roughness follows the passes' count" : "";
  }
  void renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass, PassStats& stats) override;
  // The merging radius of iteration `pass` (0-based), r_1 · (pass + 1)^((α−1)/2).
  float radius(const Scene& scene, uint64_t pass) const;

 private:
  VcmSettings settings_;
  // This pass's light subpaths: each tile's in one array, and where each pixel's is.
  struct LightSubpathRef {
    uint32_t tile, first, count;
  };
  std::vector<std::vector<bidir::Vertex>> tileVertices_;
  std::vector<LightSubpathRef> lightSubpaths_;
  size_t cachedBefore_ = 0;  // lvc: M of the previous pass (0: none yet), for the MIS weights
  // regularize: the scene's rough twins for the pass being rendered.
  std::unique_ptr<Regularization> regularization_;
};

}  // namespace lb
