#pragma once
// Variance-aware MIS (Grittmann, Georgiev, Slusallek & Křivánek 2019,
// "Variance-Aware Multiple Importance Sampling"): the balance heuristic over
// c_t n_t p_t instead of n_t p_t, where c_t is technique t's ratio of second
// moment to variance,
//     c_t = M_t / V_t = 1 + I_t² / V_t,   M_t = E[F_t²],  V_t = M_t − E[F_t]²,
// for F_t the technique's own, unweighted one-sample estimate of the pixel's
// integral (here: path tracing's light sample and BSDF sample, per path
// length). A technique whose estimate is nearly constant gets c ≫ 1 and most
// of the weight where both could sample; where both are noisy, c ≈ 1 and the
// weights are the balance heuristic's. The weights still sum to 1 at every
// point, whatever c is, so any factors, even wrong ones, leave the estimator
// unbiased: the factors only move variance.
//
// The moments are estimated from pilot passes (rendered with c = 1 and kept
// in the image), pooled over square blocks of pixels, as the authors'
// implementation does (it pools one pass over blocks of pixels; we pool every
// sample of every pilot pass in the block). A block lies inside one of the
// render loop's 16×16 tiles (pixel_tiles.h), so one thread writes it and the
// sums, and with them the image, do not depend on the thread count.
#include <cstddef>
#include <vector>

namespace lb {

enum class MisTechnique { Light = 0, Bsdf = 1 };

class VarianceAwareMis {
 public:
  // Path lengths (in segments) 2 … MaxLength get factors of their own;
  // longer paths use c = 1 (the balance heuristic).
  static constexpr int MaxLength = 8;
  // The largest factor (a technique whose estimate is constant).
  static constexpr float MaxFactor = 1e6f;

  // `block`: pixels per block side, dividing the 16-pixel tile.
  VarianceAwareMis(int width, int height, int block);

  // One nonzero unweighted estimate of technique t for a path of `segments`
  // segments through pixel (x, y). Zeros need not be recorded: the sample
  // counts are known (passes × samples per path), see finish().
  void record(int x, int y, int segments, MisTechnique t, float value);
  // Turns the pilot's sums into factors: each path drew `lightSamples`
  // light samples and one BSDF sample per vertex, `passes` times per pixel.
  void finish(int passes, int lightSamples);
  bool finished() const { return finished_; }

  // c for technique t at pixel (x, y) and path length `segments` (1 before
  // finish(), outside the tracked lengths, and where the moments are unknown).
  float factor(int x, int y, int segments, MisTechnique t) const;

  // M / V from the sums over n samples (Σx, Σx²): 1 where the mean is not
  // positive, MaxFactor where the variance is zero within rounding. Public
  // so a test can check it against the definition.
  static float factorFromSums(double sum, double sumOfSquares, double n);

 private:
  struct Sums {
    double sum = 0, squares = 0;
  };
  size_t slot(int x, int y, int segments, MisTechnique t) const;
  int block_, across_, down_;
  std::vector<Sums> sums_;      // per block, length, technique (freed by finish())
  std::vector<float> factors_;  // same layout
  std::vector<int> pixels_;     // pixels in each block (edge blocks have fewer)
  bool finished_ = false;
};

// What the path estimator needs for one camera sample: the table, the pixel,
// and whether this sample is a pilot's (records) or not (reads the factors).
struct VarianceAwareView {
  VarianceAwareMis* table;
  int x, y;
  bool learning;
  float factor(int segments, MisTechnique t) const { return learning ? 1.f : table->factor(x, y, segments, t); }
  void record(int segments, MisTechnique t, float value) const {
    if (learning && value != 0) table->record(x, y, segments, t, value);
  }
};

}  // namespace lb
