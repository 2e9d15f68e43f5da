#pragma once
// Chooses one light for next-event estimation or emission: uniformly, or in
// proportion to its power (luminance). The combined estimator divides by
// pmf(light) · pdf(point | light).
#include <memory>
#include <vector>
#include "core/lights/light.h"
#include "core/sampling.h"

namespace lb {

enum class LightSelection { Uniform, Power };

class LightSampler {
 public:
  LightSampler() = default;
  LightSampler(const std::vector<std::unique_ptr<Light>>& lights, LightSelection selection) {
    std::vector<float> weights;
    // A light that emits nothing is never chosen, by either rule: choosing it
    // would waste the sample (and, in BDPT, leave the light subpath empty).
    for (const auto& l : lights) {
      float power = luminance(l->power());
      weights.push_back(!(power > 0) ? 0.f : selection == LightSelection::Power ? power : 1.f);
    }
    // All-black lights would make any selection undefined; fall back to uniform.
    bool anyPositive = false;
    for (float w : weights) anyPositive |= w > 0;
    if (!anyPositive) std::fill(weights.begin(), weights.end(), 1.f);
    lights_.reserve(lights.size());
    for (const auto& l : lights) lights_.push_back(l.get());
    if (!weights.empty()) distribution_ = DiscreteDistribution(weights);
  }
  bool empty() const { return lights_.empty(); }
  const Light* sample(float u, float* pmf, float* uRemapped = nullptr) const {
    if (lights_.empty()) return nullptr;
    return lights_[distribution_.sample(u, pmf, uRemapped)];
  }
  float pmf(const Light* light) const { return lights_.empty() ? 0.f : distribution_.pmf(size_t(light->index)); }

 private:
  std::vector<const Light*> lights_;
  DiscreteDistribution distribution_;
};

}  // namespace lb
