#pragma once
// One-sample next-event estimation at a surface point: a light chosen by the
// scene's light sampler, a point on it, the BSDF, a shadow ray. Returns the
// unweighted contribution f·|cos|·L / (pmf·pdf) and both strategies' pdfs, so
// each integrator applies its own MIS weight.
#include <optional>
#include "core/bsdfs/bsdf.h"
#include "core/sampler.h"
#include "core/scene.h"

namespace lb {

struct DirectLightSample {
  Color contribution{0.f};  // before any MIS weight
  Vec3 wi;                  // towards the light
  float lightPdf = 0;       // pmf(light) · solid-angle pdf
  float bsdfPdf = 0;        // the BSDF's pdf of sampling wi
  bool deltaLight = false;
};

// Everything but the visibility test: the shadow ray to trace and the
// contribution it carries if unoccluded (the wavefront engine traces shadow
// rays in streams). Empty if the light sample or the BSDF value is zero.
struct DirectLightQuery {
  DirectLightSample sample;
  Ray shadowRay;
};
// `compensated`: the light's MIS-compensated density (core/lights/light.h),
// for an estimator that also samples the BSDF and weighs with these densities.
inline std::optional<DirectLightQuery> directLightQuery(const SurfaceInteraction& si, const BSDF& bsdf,
                                                        const Light* light, float pmf, float uPick, Vec2 u,
                                                        bool compensated = false) {
  if (!light || !(pmf > 0)) return std::nullopt;
  auto ls = compensated ? light->sampleLiCompensated(si.p, uPick, u) : light->sampleLi(si.p, uPick, u);
  if (!ls || ls->pdf == 0 || isBlack(ls->L)) return std::nullopt;
  BSDFEval e = bsdf.eval(si.wo, ls->wi, TransportMode::Radiance);
  Color f = e.f * absDot(ls->wi, bsdf.shadingNormal());
  if (isBlack(f)) return std::nullopt;
  float lightPdf = pmf * ls->pdf;
  return DirectLightQuery{DirectLightSample{f * ls->L / lightPdf, ls->wi, lightPdf, e.pdf, light->isDelta()},
                          si.spawnRayTo(ls->p, ls->pError, ls->n)};
}

// The light already chosen (with probability `pmf`), a point on it from
// (uPick, u). Empty if the light sample, the BSDF value or the visibility is zero.
inline std::optional<DirectLightSample> sampleDirectLight(const Scene& scene, const SurfaceInteraction& si,
                                                          const BSDF& bsdf, const Light* light, float pmf,
                                                          float uPick, Vec2 u, uint64_t& rays) {
  auto q = directLightQuery(si, bsdf, light, pmf, uPick, u);
  if (!q) return std::nullopt;
  ++rays;
  if (scene.occluded(q->shadowRay)) return std::nullopt;
  return q->sample;
}

// The light chosen by the scene's light sampler. Uses three sampler
// dimensions (1-D, 1-D, 2-D).
inline std::optional<DirectLightSample> sampleDirectLight(const Scene& scene, const SurfaceInteraction& si,
                                                          const BSDF& bsdf, Sampler& sampler, uint64_t& rays) {
  const LightSampler& lights = scene.lightSampler();
  float pmf = 0;
  const Light* light = lights.empty() ? nullptr : lights.sample(sampler.get1D(), &pmf);
  float uPick = sampler.get1D();
  Vec2 u = sampler.get2D();
  return sampleDirectLight(scene, si, bsdf, light, pmf, uPick, u, rays);
}

}  // namespace lb
