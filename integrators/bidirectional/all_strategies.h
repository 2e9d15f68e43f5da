#pragma once
// One bidirectional sample with every strategy: a camera subpath through
// `raster`, a light subpath, and each connection (s, t) they allow, weighted
// by MIS over all strategies (Veach 1997 ch. 10; pbrt-v3 §16.3). Shared by
// `bdpt` (one such sample per pixel and pass) and by primary-sample-space MLT
// over BDPT (`mlt` with base: bdpt, Kelemen et al. 2002 §4), which draws the
// camera subpath, the light subpath and the connections from three separate
// streams of its primary sample vector; bdpt passes one sampler for all three,
// with each decision at a fixed dimension (BdptDimensions).
#include <vector>
#include "core/sampler.h"
#include "integrators/bidirectional/connect.h"
#include "integrators/bidirectional/cost_split.h"
#include "integrators/bidirectional/strategy_factors.h"
#include "integrators/bidirectional/subpaths.h"
#include "integrators/bidirectional/verification.h"
#include "integrators/path_length.h"

namespace lb::bidir {

struct SampleStreams {
  Sampler& camera;      // the camera subpath's walk (the raster position is the caller's)
  Sampler& light;       // the light subpath
  Sampler& connection;  // what connect() draws (s = 1 light points)
  // One sampler for all three (bdpt): each decision at a fixed dimension,
  // BdptDimensions. Otherwise each stream is drawn in order (MLT).
  bool fixedDimensions = false;
  // regularize: this pass's rough twins (core/bsdfs/regularization.h), or null.
  const Regularization* regularization = nullptr;
  // mis: variance_aware: the learned factors (finished), or null. With them
  // a path of up to StrategyFactors::MaxSegments segments is weighted by the
  // walk over c·p (strategy_factors.h); `mis` must then be the balance heuristic.
  const StrategyFactors* factors = nullptr;
};

// BDPT's dimensions in one sampler, so that Sobol', ZSobol and Halton
// stratify the light subpath and the connections too, not only the camera
// subpath's first vertices: the raster position 0–1 (the caller's), the
// light's emission 2–7, then 12 per depth k ≥ 1: the camera subpath's
// scattering at its vertex k, the light subpath's at its vertex k, and next-
// event estimation (s = 1) at camera vertex k (as the path estimator gives
// each vertex its range, path_estimator.h).
struct BdptDimensions {
  static constexpr uint32_t Emission = 2, First = 8, PerDepth = 12;
  static WalkDimensions camera() { return {First, PerDepth, 0}; }
  static WalkDimensions light() { return {First + 4, PerDepth, Emission}; }
  static uint32_t nee(int cameraVertex) { return First + PerDepth * uint32_t(cameraVertex - 1) + 8; }
};

// The vertex arrays a sample reuses; sized once from the path length
// ("unlimited" depth is capped at 4096 segments).
struct SubpathBuffers {
  std::vector<Vertex> camera, light;
  SubpathBuffers() = default;
  explicit SubpathBuffers(const PathLength& length) { fit(length); }
  void fit(const PathLength& length);  // cheap when already sized for `length`
};

// Calls onStrategy(s, t, connection) for each strategy with a non-zero
// weighted contribution `c.L · c.weight` (possibly non-finite: the caller
// counts and drops those). For t = 1 the contribution belongs at c.raster,
// otherwise at the sample's own raster. (A template, not std::function: the
// callback runs once per connection and its captures would be allocated
// once per pixel.)
template <typename OnStrategy>
void sampleAllStrategies(const Scene& scene, const SampleStreams& streams, const PathLength& length,
                         MisWeighting mis, Vec2 raster, SubpathBuffers& buffers, uint64_t& rays,
                         OnStrategy&& onStrategy) {
  const int maxSeg = length.maxSegments();
  const bool fixed = streams.fixedDimensions;
  int nCamera = generateCameraSubpath(scene, streams.camera, length, raster, buffers.camera, rays,
                                      fixed ? BdptDimensions::camera() : WalkDimensions{}, WalkStop::AtLength,
                                      streams.regularization);
  int nLight;
  {
    PhaseScope phase(Phase::LightSubpaths);
    nLight = generateLightSubpath(scene, streams.light, length, buffers.light, rays,
                                  fixed ? BdptDimensions::light() : WalkDimensions{}, streams.regularization);
  }
  computePartialSums(scene, mis, Techniques{}, buffers.camera, nCamera, SubpathSide::Camera);
  computePartialSums(scene, mis, Techniques{}, buffers.light, nLight, SubpathSide::Light);
  // s = 1 samples its own light point, so it runs even when the light
  // subpath is empty (emission sampling failed).
  for (int t = 1; t <= nCamera; ++t)
    for (int s = 0; s <= std::max(nLight, 1); ++s) {
      int segments = s + t - 1;
      if ((s == 1 && t == 1) || segments < 1 || segments > maxSeg) continue;  // (1,1) is covered by (0,2) (pbrt-v3)
      if (fixed && s == 1) streams.connection.setDimension(BdptDimensions::nee(t - 1));
      Connection c = connect(scene, streams.connection, mis, buffers.light, buffers.camera, s, t, rays);
      if (isBlack(c.L) || c.weight == 0) continue;
      if (streams.factors && streams.factors->covers(s, t) && s + t > 2) {
        PhaseScope weights(Phase::Weights);
        Vec2 where = t == 1 ? c.raster : raster;  // the pixel the path lands in, whichever strategy made it
        std::function<double(int, int)> factor = [&](int sOther, int tOther) {
          return streams.factors->factor(where, sOther, tOther);
        };
        c.weight = techniqueWeightsByWalk(scene, mis, Techniques{}, buffers.light, buffers.camera, c.sampled, s, t,
                                          nullptr, &factor)
                       .connection;
        if (c.weight == 0) continue;
      }
      onStrategy(s, t, c);
    }
}

}  // namespace lb::bidir
