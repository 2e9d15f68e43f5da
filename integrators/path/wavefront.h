#pragma once
// The path tracer's wavefront engine (`path` with `engine: wavefront`): the
// lectures' "efficient implementation" of a path tracer (no recursion, ray
// storage allocated once and reused, live rays packed so finished paths cost
// nothing, tiles for threads), in the form of Laine, Karras & Aila 2013,
// "Megakernels considered harmful": paths advance one bounce at a time, in
// batches, and every stage traces its rays as one stream through Embree
// (rtcIntersect1M, rtcOccluded1M).
//
// Queue design, per batch of 64×64 pixels (a fixed cut of the image, so the
// result does not depend on the thread count; TBB runs batches in parallel,
// each on its worker's Workspace, allocated once and reused by later batches
// and passes):
//   paths    one PathState, pixel and running L per pixel of the batch;
//   active   the indices of the live paths, compacted after every bounce;
//   rayhits  the active paths' rays, one stream per bounce (COHERENT for
//            camera rays, INCOHERENT after);
//   shadows  the light samples the bounce made (ray, contribution, owner),
//            one occlusion stream per bounce.
// Each bounce: (1) intersect the active stream; (2) shade every active path in
// order (PathEstimator::shadeVertex: emission into L, light samples appended to
// the shadow queue; PathEstimator::scatter: the next ray, or the path ends);
// (3) trace the shadow stream and add the unoccluded contributions to their
// owners' L in queue order. After the last bounce each L goes to the film.
//
// Same estimator, same numbers: shadeVertex and scatter are the single-ray
// engine's own code; the sampler is restarted at (pixel, pass) before each
// path's bounce, which costs nothing in randomness because every value is a
// function of (seed, pixel, sample, dimension) and each vertex's dimensions
// are fixed (path_tracer.h); and a path's additions to L come in the same
// order. The two engines differ only where Embree's stream traversal returns
// a hit different from its single-ray traversal. Not supported:
// first_bounce_samples > 1 (branching paths), refused when read.
#include <tbb/enumerable_thread_specific.h>
#include <vector>
#include "integrators/integrator.h"
#include "integrators/path_estimator/path_estimator.h"

namespace lb {

class WavefrontEngine {
 public:
  static constexpr int BatchSize = 64;  // pixels per side of a batch

  explicit WavefrontEngine(const PathEstimator& estimator) : estimator_(estimator) {}
  void renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass, PassStats& stats);

 private:
  struct Workspace {
    std::unique_ptr<Sampler> sampler;
    std::vector<PathState> paths;
    std::vector<Color> L;
    std::vector<float> filterWeight;  // each path's pixel-filter weight (core/filter.h)
    std::vector<uint64_t> pixel;
    std::vector<int> active, nextActive;
    std::vector<RTCRayHit> rayhits;
    std::vector<ShadowRequest> shadows;
    std::vector<int> shadowOwner;
    std::vector<RTCRay> shadowRays;
  };
  // One batch: pixels [x0, x1) × [y0, y1); returns the rays traced.
  uint64_t renderBatch(Workspace& w, const Scene& scene, Film& film, uint64_t pass, int x0, int y0, int x1, int y1) const;

  const PathEstimator& estimator_;
  tbb::enumerable_thread_specific<Workspace> workspaces_;
};

}  // namespace lb
