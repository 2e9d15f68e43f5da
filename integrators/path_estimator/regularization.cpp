#include "integrators/path_estimator/regularization.h"

#include <cmath>

namespace lb {

float RegularizationSettings::roughness(uint64_t pass) const {
  return initialRoughness * float(std::pow(double(pass) + 1, -double(exponent)));
}

void Regularization::prepare(const Scene& scene, uint64_t pass) {
  roughness_ = settings_.roughness(pass);
  twins_.clear();
  for (size_t id = 0; id < scene.materialCount(); ++id) {
    const Material& m = scene.material(int(id));
    if (auto twin = m.mollified(roughness_)) twins_.emplace(&m, std::move(twin));
  }
}

}  // namespace lb
