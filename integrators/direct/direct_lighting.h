#pragma once
// Direct lighting: light that reaches the camera after at most one bounce —
// the emitters seen directly, plus light from an emitter reflected once
// (paths of at most two segments, the path tracer's max_depth: 2). Each
// bounce combines a light sample and a BSDF sample with MIS (Veach 1997, §9.2).
// docs/writing-an-integrator.md builds this file step by step.
#include "core/params.h"
#include "integrators/integrator.h"

namespace lb {

struct DirectLightingSettings {
  bool mis = true;  // false: the light sample alone (the BSDF sample counts only delta lobes)
  static DirectLightingSettings read(Params& p);
};

class DirectLighting final : public PixelIntegrator {
 public:
  // Unbiased with independent passes: chunks of passes split a render exactly.
  std::string splitRefusal() const override { return ""; }
  explicit DirectLighting(DirectLightingSettings s) : settings_(s) {}

 protected:
  Color Li(const Ray& ray, const Scene& scene, Sampler& sampler, uint64_t& rays) const override;

 private:
  DirectLightingSettings settings_;
};

}  // namespace lb
