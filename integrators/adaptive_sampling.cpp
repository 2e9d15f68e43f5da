#include "integrators/adaptive_sampling.h"

#include <cmath>

namespace lb {

namespace {
constexpr double RelativeEpsilon = 0.01;  // as relMSE's (experiments/metrics.h)
constexpr double UniformShare = 0.1;      // of each pass, spread over every pixel
constexpr double MaxWeightRatio = 16;     // a pixel's weight, at most this times the mean
constexpr int SmoothingRadius = 2;        // σ² and m averaged over 5 × 5 pixels
}  // namespace

AdaptiveSettings AdaptiveSettings::read(Params& p) {
  AdaptiveSettings s;
  s.enabled = true;
  s.passes =
      p.getInt("passes", 8, {"uniform passes before adapting (each half gets every other one)", Range::atLeast(4)});
  s.targetRelativeError = p.getFloat(
      "target_relative_error", 0.f,
      {"pixels whose estimated relative error is below this get no more samples (0: none)", Range::atLeast(0)});
  p.checkUnused();
  return s;
}

AdaptiveSampling::AdaptiveSampling(int width, int height, AdaptiveSettings settings)
    : settings_(settings),
      width_(width),
      height_(height),
      deciding_(width, height),
      drawn_(size_t(width) * height, 0) {}

bool AdaptiveSampling::renderPass(const Scene& scene, PixelIntegrator& integrator, Film& estimate,
                                  const Sampler& prototype, uint64_t pass, PassStats& stats) {
  std::vector<uint32_t> count = pass < uint64_t(settings_.passes) ? std::vector<uint32_t>(drawn_.size(), 1) : plan();
  bool any = false;
  for (uint32_t c : count) any |= c > 0;
  if (!any) return false;
  // The deciding half's own stream: independent of the image's samples
  // whatever the scene's sampler (a stratified or low-discrepancy sequence
  // ties a pixel's samples together; its even half alone is a prefix of it).
  IndependentSampler decidingSampler(hashValues(prototype.seed(), 0xdec1de));
  integrator.renderSamples(scene, estimate, prototype, deciding_, decidingSampler, count, drawn_, stats);
  for (size_t i = 0; i < count.size(); ++i) drawn_[i] += count[i];
  return true;
}

std::vector<uint32_t> AdaptiveSampling::plan() const {
  Image mean = deciding_.image(), variance = deciding_.varianceOfMean();
  const size_t pixels = drawn_.size();
  // Per pixel, from the deciding half: the per-sample variance σ² (the
  // variance of its mean times its count) and the mean luminance.
  std::vector<double> sampleVariance(pixels, 0.0), meanLuminance(pixels, 0.0);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      size_t i = size_t(y) * width_ + x;
      double n = double(deciding_.samples(x, y));
      const Color& v = variance.at(x, y);
      double s2 = (double(v.r) + v.g + v.b) / 3 * n;
      sampleVariance[i] = n >= 2 && std::isfinite(s2) ? s2 : 0.0;
      meanLuminance[i] = luminance(mean.at(x, y));
    }
  std::vector<double> weight(pixels, 0.0);
  std::vector<char> open(pixels, 0);  // not yet at the target
  double total = 0;
  size_t opened = 0;
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      // Averaged over the pixel's neighbourhood: a few samples of a
      // heavy-tailed pixel often show no variance at all (every one missed
      // the rare bright paths), and that luck would starve it.
      double s2 = 0, m = 0, taps = 0;
      for (int v = std::max(0, y - SmoothingRadius); v <= std::min(height_ - 1, y + SmoothingRadius); ++v)
        for (int u = std::max(0, x - SmoothingRadius); u <= std::min(width_ - 1, x + SmoothingRadius); ++u) {
          size_t j = size_t(v) * width_ + u;
          s2 += sampleVariance[j], m += meanLuminance[j], taps += 1;
        }
      s2 /= taps, m /= taps;
      size_t i = size_t(y) * width_ + x;
      double n = std::max(1.0, double(deciding_.samples(x, y)));
      double scale = std::sqrt(m * m + RelativeEpsilon);
      if (settings_.targetRelativeError > 0 && std::sqrt(s2 / n) / scale < settings_.targetRelativeError) continue;
      open[i] = 1, ++opened;
      weight[i] = std::sqrt(s2) / scale;  // σ_p / √(m_p² + ε)
      total += weight[i];
    }
  std::vector<uint32_t> count(pixels, 0);
  if (opened == 0) return count;
  // σ_p is estimated from few samples, and one outlier makes it huge: a cap
  // keeps one pixel from claiming a whole pass on one firefly.
  const double cap = MaxWeightRatio * total / double(opened);
  total = 0;
  for (double& w : weight) total += (w = std::min(w, cap));
  // One pass's worth (one sample per pixel on average): a share spread over
  // the open pixels, the rest in proportion to the weights.
  const double budget = double(pixels);
  const double uniform = (total > 0 ? UniformShare : 1.0) * budget / double(opened);
  const double perWeight = total > 0 ? (1 - UniformShare) * budget / total : 0;
  double carry = 0;
  for (size_t i = 0; i < pixels; ++i) {
    if (!open[i]) continue;
    carry += uniform + perWeight * weight[i];
    double whole = std::floor(carry);
    count[i] = uint32_t(whole);
    carry -= whole;
  }
  return count;
}

}  // namespace lb
