#pragma once
// Light tracing (particle tracing splatted to the camera): the t = 1
// strategies of Veach 1997 §10.2. Each pass traces one light path per pixel:
// choose a light by power, sample an emitted ray, and at the light point (area
// lights) and every non-delta surface vertex connect to the pinhole, splatting
// β·f·|cos|·We/p at the raster position. Paths continue by importance-mode BSDF
// sampling with Russian roulette.
//
//   max_depth, rr, rr_depth   path length in segments, camera connection
//                             included, and roulette (path_length.h)
//
// Cannot see: emitters through delta chains ending at the camera (L…S E),
// point and spot lights themselves, and a directly visible environment.
#include "core/params.h"
#include "integrators/path_length.h"
#include "integrators/integrator.h"

namespace lb {

struct LightTracerSettings {
  PathLength length;
  static LightTracerSettings read(Params& p);
};

class LightTracer final : public Integrator {
 public:
  // Unbiased with independent passes: chunks of passes split a render exactly.
  std::string splitRefusal() const override { return ""; }
  explicit LightTracer(LightTracerSettings s) : settings_(s) {}
  void renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass, PassStats& stats) override;

 private:
  void tracePath(const Scene& scene, Sampler& sampler, std::vector<Splat>& splats, uint64_t& rays) const;
  LightTracerSettings settings_;
};

}  // namespace lb
