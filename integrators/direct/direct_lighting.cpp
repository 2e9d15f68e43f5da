#include "integrators/direct/direct_lighting.h"
#include "core/bsdfs/bsdf.h"
#include "core/sampling.h"
#include "integrators/direct_light.h"

namespace lb {

DirectLightingSettings DirectLightingSettings::read(Params& p) {
  DirectLightingSettings s;
  s.mis = p.getBool("mis", true, "weight the light and BSDF samples by the power heuristic; false: light samples only");
  p.checkUnused();  // an unknown key is an error naming the valid ones
  return s;
}

Color DirectLighting::Li(const Ray& ray, const Scene& scene, Sampler& sampler, uint64_t& rays) const {
  // The camera ray: emitters seen directly (an area light, or the environment).
  SurfaceInteraction si;
  ++rays;
  if (!scene.intersect(ray, si)) {
    Color L(0.f);
    for (const Light* env : scene.infiniteLights()) L += env->Le(ray.d);
    return L;
  }
  Color L = si.emitter ? si.emitter->L(si.ng, si.wo) : Color(0.f);
  if (!si.material) return L;
  BSDF bsdf(si);
  const LightSampler& lights = scene.lightSampler();

  // Strategy 1, the light sample: a point on a light, checked for visibility.
  if (auto d = sampleDirectLight(scene, si, bsdf, sampler, rays)) {
    bool weighted = settings_.mis && !d->deltaLight && !bsdf.isDelta();
    L += d->contribution * (weighted ? powerHeuristic(d->lightPdf, d->bsdfPdf) : 1.f);
  }

  // Strategy 2, the BSDF sample: a direction that may hit an emitter.
  Vec2 uDir = sampler.get2D();  // the direction's two dimensions, then the lobe's (core/sampler.h)
  float uLobe = sampler.get1D();
  auto bs = bsdf.sample(si.wo, uLobe, uDir, TransportMode::Radiance);
  if (!bs || (!settings_.mis && !bs->isDelta())) return L;  // without MIS, only delta lobes (no light sample reaches them)
  auto weight = [&](const Light* light, float pdfLi) {
    return bs->isDelta() ? 1.f : powerHeuristic(bs->pdf, lights.pmf(light) * pdfLi);
  };
  Ray next = si.spawnRay(bs->wi);
  SurfaceInteraction hit;
  ++rays;
  if (!scene.intersect(next, hit)) {
    for (const Light* env : scene.infiniteLights())
      L += bs->weight * env->Le(next.d) * weight(env, env->pdfLi(si.p, next.d, {}, {}));
  } else if (hit.emitter) {
    L += bs->weight * hit.emitter->L(hit.ng, hit.wo) * weight(hit.emitter, hit.emitter->pdfLi(si.p, next.d, hit.p, hit.ng));
  }
  return L;
}

}  // namespace lb
