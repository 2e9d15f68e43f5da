#include "core/bsdfs/regularization.h"

#include <cmath>

namespace lb {

RegularizationSettings RegularizationSettings::read(Params& p) {
  RegularizationSettings s;
  s.enabled = p.getBool("regularize", false,
                        "path-space regularization (Kaplanyan & Dachsbacher 2013): a delta vertex with a non-delta one "
                        "between it and the camera scatters by a GGX twin whose roughness shrinks pass by pass; "
                        "consistent, not unbiased");
  if (s.enabled || p.describing()) {
    p.setCondition("regularize: true");
    s.initialRoughness =
        p.getFloat("regularize_roughness", 0.1f, {"α_0, the twins' GGX roughness in the first pass", Range::open(0, 1)});
    s.exponent = p.getFloat(
        "regularize_exponent", 1.f / 6.f,
        {"λ: pass k's roughness is α_0 (k + 1)^-λ; consistent for 0 < λ < 1/2, fixed at 0", Range{0.0, 0.5, false, true}});
    p.setCondition("");
  }
  return s;
}

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
