#include "integrators/path_estimator/variance_aware_mis.h"
#include <algorithm>
#include <cmath>

namespace lb {

namespace {
constexpr int Lengths = VarianceAwareMis::MaxLength - 1;  // lengths 2 … MaxLength
constexpr int Techniques = 2;
}  // namespace

VarianceAwareMis::VarianceAwareMis(int width, int height, int block)
    : block_(block),
      across_((width + block - 1) / block),
      down_((height + block - 1) / block) {
  size_t blocks = size_t(across_) * size_t(down_);
  sums_.resize(blocks * Lengths * Techniques);
  pixels_.resize(blocks);
  for (int by = 0; by < down_; ++by)
    for (int bx = 0; bx < across_; ++bx)
      pixels_[size_t(by) * size_t(across_) + size_t(bx)] =
          (std::min(width, (bx + 1) * block) - bx * block) * (std::min(height, (by + 1) * block) - by * block);
}

size_t VarianceAwareMis::slot(int x, int y, int segments, MisTechnique t) const {
  size_t b = size_t(y / block_) * size_t(across_) + size_t(x / block_);
  return (b * Lengths + size_t(segments - 2)) * Techniques + size_t(t);
}

void VarianceAwareMis::record(int x, int y, int segments, MisTechnique t, float value) {
  if (finished_ || segments < 2 || segments > MaxLength) return;
  Sums& s = sums_[slot(x, y, segments, t)];
  s.sum += value;
  s.squares += double(value) * double(value);
}

float VarianceAwareMis::factorFromSums(double sum, double sumOfSquares, double n) {
  if (!(n > 0)) return 1.f;
  double mean = sum / n, moment = sumOfSquares / n;
  double variance = moment - mean * mean;
  if (!(mean > 0)) return 1.f;  // the technique found nothing here: no evidence either way
  // A constant estimate (zero variance, or within rounding of it) deserves
  // all the weight: c = M/V grows without bound as V → 0. Cap it so the
  // weights stay finite; 1e6 already gives the technique all the weight
  // wherever the other's density is not a million times larger.
  if (variance <= 1e-9 * moment) return MaxFactor;
  return float(std::min(moment / variance, double(MaxFactor)));
}

void VarianceAwareMis::finish(int passes, int lightSamples) {
  factors_.assign(sums_.size(), 1.f);
  for (size_t b = 0; b < pixels_.size(); ++b)
    for (int l = 0; l < Lengths; ++l)
      for (int t = 0; t < Techniques; ++t) {
        size_t i = (b * Lengths + size_t(l)) * Techniques + size_t(t);
        double perPixel = t == int(MisTechnique::Light) ? double(passes) * lightSamples : double(passes);
        factors_[i] = factorFromSums(sums_[i].sum, sums_[i].squares, perPixel * pixels_[b]);
      }
  sums_ = {};
  finished_ = true;
}

float VarianceAwareMis::factor(int x, int y, int segments, MisTechnique t) const {
  if (!finished_ || segments < 2 || segments > MaxLength) return 1.f;
  return factors_[slot(x, y, segments, t)];
}

}  // namespace lb
