#pragma once
// Adaptive sampling for integrators that estimate each pixel from its own
// camera samples (PixelIntegrator): after `passes` uniform passes, each pass's
// worth of samples (one per pixel on average) goes to the pixels in
// proportion to their estimated relative error.
//
// Deciding a pixel's sample count from the samples that estimate it biases
// the estimate (a pixel whose samples happened to agree stops early, and its
// luck is frozen in). So the samples are split into two independent halves by
// the parity of their index (Rousselle et al. 2012 use such dual buffers for
// the same reason): the odd half only decides — its per-pixel variance and
// mean set the next pass's counts — and the even half only estimates: the
// image is its mean. The deciding half draws its numbers from an independent
// sampler of its own seed, the estimating half from the scene's sampler (its
// samples 0, 1, 2, … of the pixel), so the even half's counts depend on the
// odd half alone, which is independent of the even half's samples whatever
// the scene's sampler, and the image is UNBIASED (tested):
// E[Σ_i L_i / n | n] = μ for any n chosen without them. The price is that
// half of the samples never reach the image.
//
// Allocation: pixel p's share is proportional to its per-sample relative
// deviation s_p = σ_p / √(m_p² + 0.01) (the relative error the experiments'
// relMSE measures, ε = 0.01), σ_p and m_p from the deciding half: the
// allocation that minimises Σ_p relMSE_p for a fixed total (n_p ∝ s_p, a
// Lagrange-multiplier argument). σ_p comes from few samples: σ_p² and m_p
// are averaged over the 5×5 pixels around p (a heavy-tailed pixel's few
// samples often show no variance at all, and that luck would starve it: on
// the narrow door scene, unsmoothed, the error tripled), and s_p is capped
// at 16 times the mean of the pixels' (one firefly would claim a pass). A tenth of each pass is spread uniformly, so
// every pixel's count grows without bound (the estimate is also consistent)
// and a pixel whose pilot saw no variance (a caustic not yet found) is not
// abandoned. Pixels whose estimated relative error σ_p/√(n_p)/√(m_p² + 0.01)
// is below `target_relative_error` get no more samples; when all are below
// it, the render stops early.
//
// Counts are rounded by carrying the fractional remainder from pixel to
// pixel in scanline order; they depend only on the deciding half's sums, so
// images are the same for a seed whatever the thread count.
#include <string>
#include <vector>
#include "core/params.h"
#include "integrators/integrator.h"

namespace lb {

struct AdaptiveSettings {
  bool enabled = false;
  int passes = 8;                  // uniform passes first (at least 4: two samples per pixel in each half)
  double targetRelativeError = 0;  // 0: none
  // Reads `adaptive: {passes, target_relative_error}` (an experiment's configuration).
  static AdaptiveSettings read(Params& p);
};

class AdaptiveSampling {
 public:
  AdaptiveSampling(int width, int height, AdaptiveSettings settings);
  // One pass's worth of samples into `estimate` (the even half) and the
  // deciding half; false, rendering nothing, when every pixel has reached
  // the target.
  bool renderPass(const Scene& scene, PixelIntegrator& integrator, Film& estimate, const Sampler& prototype,
                  uint64_t pass, PassStats& stats);
  const Film& decidingHalf() const { return deciding_; }
  // Samples drawn per pixel, both halves (scanline order).
  const std::vector<uint64_t>& drawn() const { return drawn_; }

 private:
  std::vector<uint32_t> plan() const;
  AdaptiveSettings settings_;
  int width_, height_;
  Film deciding_;
  std::vector<uint64_t> drawn_;
};

}  // namespace lb
