#include "integrators/bidirectional/strategy_factors.h"
#include <algorithm>
#include "integrators/path_estimator/variance_aware_mis.h"

namespace lb::bidir {

StrategyFactors::StrategyFactors(int width, int height, int block)
    : width_(width), height_(height), block_(block), across_((width + block - 1) / block),
      down_((height + block - 1) / block) {
  size_t blocks = size_t(across_) * size_t(down_);
  sums_.resize(blocks * Slots);
  pixels_.resize(blocks);
  for (int by = 0; by < down_; ++by)
    for (int bx = 0; bx < across_; ++bx)
      pixels_[size_t(by) * size_t(across_) + size_t(bx)] =
          (std::min(width, (bx + 1) * block) - bx * block) * (std::min(height, (by + 1) * block) - by * block);
}

void StrategyFactors::record(int x, int y, int s, int t, double value) {
  if (finished_ || !covers(s, t) || x < 0 || y < 0 || x >= width_ || y >= height_) return;
  Sums& sums = sums_[block(x, y) * Slots + slot(s, t)];
  sums.sum += value;
  sums.squares += value * value;
}

void StrategyFactors::finish(int passes) {
  factors_.assign(sums_.size(), 1.f);
  for (size_t b = 0; b < pixels_.size(); ++b)
    for (size_t k = 0; k < size_t(Slots); ++k) {
      const Sums& s = sums_[b * Slots + k];
      factors_[b * Slots + k] = VarianceAwareMis::factorFromSums(s.sum, s.squares, double(passes) * pixels_[b]);
    }
  sums_ = {};
  finished_ = true;
}

double StrategyFactors::factor(Vec2 raster, int s, int t) const {
  if (!finished_ || !covers(s, t)) return 1;
  int x = std::clamp(int(std::floor(raster.x)), 0, width_ - 1), y = std::clamp(int(std::floor(raster.y)), 0, height_ - 1);
  return factors_[block(x, y) * Slots + slot(s, t)];
}

}  // namespace lb::bidir
