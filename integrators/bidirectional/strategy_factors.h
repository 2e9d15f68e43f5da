#pragma once
// Variance-aware MIS for bidirectional path tracing (Grittmann, Georgiev,
// Slusallek & Křivánek 2019): the balance heuristic over c_{s,t} p_{s,t}
// instead of p_{s,t}, with c = M/V the ratio of second moment to variance
// of strategy (s, t)'s own, unweighted estimate of a pixel's light over
// paths of s + t − 1 segments (the factor and its caps:
// integrators/path_estimator/variance_aware_mis.h, which does the same for
// the path tracer's two techniques). The weights of a path's strategies
// still sum to 1 for any factors, provided every strategy of that path reads
// its factor from the same place: the block of the pixel the path lands in
// (its raster position), whichever strategy sampled it.
//
// The factors cannot ride on the O(1) partial sums (mis.h): a vertex's sum
// is built before the path's length, and with it the other strategies'
// (s', t'), is known, and a per-strategy factor would have to split as a
// function of s' times a function of t' for every length. So a weighted
// strategy walks its path (techniqueWeightsByWalk, O(s + t)); paths longer
// than MaxSegments keep the O(1) balance weights (c = 1), all their
// strategies alike.
//
// One pass's estimate of strategy (s, t) for a pixel: for t ≥ 2 the camera
// sample's unweighted contribution (one per pass); for t = 1 the sum of the
// pass's light-tracing splats that land in the pixel (the pass's light paths
// estimate each pixel once together). The moments are pooled over square
// blocks inside the render loop's 16×16 tiles; t ≥ 2 records are made by the
// tile's thread, t = 1 ones after the pass in a fixed order, so the factors,
// and the image, do not depend on the thread count.
#include <vector>
#include "core/math.h"

namespace lb::bidir {

class StrategyFactors {
 public:
  // Paths of 1 … MaxSegments segments get factors (strategies s = 0 … k + 1
  // for a path of k segments, t = k + 1 − s).
  static constexpr int MaxSegments = 8;

  // `block`: pixels per block side, dividing the 16-pixel tile.
  StrategyFactors(int width, int height, int block);
  int width() const { return width_; }
  int height() const { return height_; }

  // One pass's nonzero estimate of strategy (s, t) for pixel (x, y); zeros
  // are implied by the pass count (finish()).
  void record(int x, int y, int s, int t, double value);
  void finish(int passes);
  bool finished() const { return finished_; }
  // c of strategy (s, t) for a path landing at `raster` (1 before finish()
  // and for paths longer than MaxSegments).
  double factor(Vec2 raster, int s, int t) const;
  bool covers(int s, int t) const { return s >= 0 && t >= 1 && s + t - 1 >= 1 && s + t - 1 <= MaxSegments; }

 private:
  static constexpr int Slots = (MaxSegments + 2) * (MaxSegments + 2);  // (s, t), t ≥ 1
  size_t block(int x, int y) const { return size_t(y / block_) * size_t(across_) + size_t(x / block_); }
  static size_t slot(int s, int t) { return size_t(s) * (MaxSegments + 2) + size_t(t); }
  struct Sums {
    double sum = 0, squares = 0;
  };
  int width_, height_, block_, across_, down_;
  std::vector<Sums> sums_;       // per block and slot (freed by finish())
  std::vector<float> factors_;   // same layout
  std::vector<int> pixels_;      // pixels in each block
  bool finished_ = false;
};

}  // namespace lb::bidir
