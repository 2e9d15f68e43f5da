#include "core/sampling.h"

namespace lb {

DiscreteDistribution::DiscreteDistribution(const std::vector<float>& weights) {
  double sum = 0;
  for (float w : weights) sum += w;
  total_ = float(sum);
  pmf_.resize(weights.size());
  cdf_.resize(weights.size() + 1);
  cdf_[0] = 0;
  double running = 0;
  for (size_t i = 0; i < weights.size(); ++i) {
    pmf_[i] = sum > 0 ? float(weights[i] / sum) : 1.f / weights.size();
    running += sum > 0 ? weights[i] / sum : 1.0 / weights.size();
    cdf_[i + 1] = float(running);
  }
  cdf_.back() = 1.f;
}

size_t DiscreteDistribution::sample(float u, float* pmf, float* uRemapped) const {
  size_t i = size_t(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin()) - 1;
  i = std::min(i, pmf_.size() - 1);
  // Never return a zero-probability entry (rounding can leave u in a gap of
  // trailing zero weights): step forward, else back to the last positive one.
  while (pmf_[i] == 0 && i + 1 < pmf_.size()) ++i;
  while (pmf_[i] == 0 && i > 0) --i;
  if (pmf) *pmf = pmf_[i];
  if (uRemapped) {
    float width = cdf_[i + 1] - cdf_[i];
    *uRemapped = width > 0 ? glm::clamp((u - cdf_[i]) / width, 0.f, OneMinusEpsilon) : 0.5f;
  }
  return i;
}

}  // namespace lb
