#pragma once
// The start of every path traced from the lights (light tracing, BDPT's light
// subpath, photons): a light chosen by the scene's light sampler, an emitted
// ray, and the throughput Le·|cos| / (pmf · pdfPos · pdfDir). Point-like
// sources (no normal) count cos = 1.
#include <optional>
#include "core/sampler.h"
#include "core/scene.h"

namespace lb {

struct EmittedRay {
  const Light* light;
  float pmf;             // probability of choosing `light`
  LightEmission emission;
  Color beta;            // throughput after the emission
};

// Uses six sampler dimensions in four draws (1-D, 1-D, 2-D, 2-D). Empty if there is no
// light or the sample carries nothing.
inline std::optional<EmittedRay> sampleEmission(const Scene& scene, Sampler& sampler) {
  const LightSampler& lights = scene.lightSampler();
  if (lights.empty()) return std::nullopt;
  float pmf;
  const Light* light = lights.sample(sampler.get1D(), &pmf);
  float uPick = sampler.get1D();
  Vec2 uPos = sampler.get2D(), uDir = sampler.get2D();
  auto e = light->sampleLe(uPick, uPos, uDir);
  if (!e || e->pdfPos == 0 || e->pdfDir == 0 || isBlack(e->Le)) return std::nullopt;
  float cos = glm::dot(e->n, e->n) > 0 ? absDot(e->n, e->ray.d) : 1.f;
  return EmittedRay{light, pmf, *e, e->Le * cos / (pmf * e->pdfPos * e->pdfDir)};
}

}  // namespace lb
