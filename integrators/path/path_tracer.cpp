#include "integrators/path/path_tracer.h"
#include "core/bsdfs/bsdf.h"
#include "integrators/direct_light.h"
#include "core/sampling.h"

namespace lb {

PathTracerSettings PathTracerSettings::read(Params& p) {
  PathTracerSettings s;
  std::string sampling = p.getChoice("sampling", "bsdf", {"bsdf", "cosine", "uniform"},
                                     "how the next direction is sampled at a surface");
  s.sampling = sampling == "bsdf" ? DirectionSampling::Bsdf
               : sampling == "cosine" ? DirectionSampling::Cosine
                                      : DirectionSampling::Uniform;
  s.nee = p.getBool("nee", true, "next-event estimation: a shadow ray to a sampled light point at each vertex");
  std::string mis = p.getChoice("mis", "power", {"power", "balance", "none"},
                                "weights of NEE against the sampled direction hitting a light (Veach 1997, 9.2)");
  s.mis = mis == "power" ? MisHeuristic::Power : mis == "balance" ? MisHeuristic::Balance : MisHeuristic::None;
  s.length = PathLength::read(p);
  p.checkUnused();
  return s;
}

float PathTracer::misWeight(float pdfThis, float pdfOther) const {
  switch (settings_.mis) {
    case MisHeuristic::Power: return powerHeuristic(pdfThis, pdfOther);
    case MisHeuristic::Balance: return balanceHeuristic(pdfThis, pdfOther);
    default: return 1.f;
  }
}

namespace {

// Hemisphere strategies for non-delta surfaces. For transmissive materials the
// side is chosen with probability 1/2, so both hemispheres are covered.
struct DirectionChoice {
  Vec3 wi;
  float pdf;
};

DirectionChoice sampleHemisphere(DirectionSampling strategy, const BSDF& bsdf, const Vec3& woWorld, float uSide, Vec2 u) {
  Vec3 local = strategy == DirectionSampling::Cosine ? sampleCosineHemisphere(u) : sampleUniformHemisphere(u);
  float pdf = strategy == DirectionSampling::Cosine ? cosineHemispherePdf(local.z) : uniformHemispherePdf();
  bool below = glm::dot(woWorld, bsdf.shadingNormal()) < 0;
  if (bsdf.material().hasTransmission()) {
    pdf *= 0.5f;
    if (uSide < 0.5f) below = !below;
  }
  if (below) local.z = -local.z;
  return {bsdf.frame().toWorld(local), pdf};
}

float hemispherePdf(DirectionSampling strategy, const BSDF& bsdf, const Vec3& woWorld, const Vec3& wiWorld) {
  float cosWi = glm::dot(wiWorld, bsdf.shadingNormal());
  bool sameSide = cosWi * glm::dot(woWorld, bsdf.shadingNormal()) > 0;
  bool transmissive = bsdf.material().hasTransmission();
  if (!sameSide && !transmissive) return 0;
  float pdf = strategy == DirectionSampling::Cosine ? std::abs(cosWi) * InvPi : uniformHemispherePdf();
  return transmissive ? 0.5f * pdf : pdf;
}

}  // namespace

Color PathTracer::Li(const Ray& cameraRay, const Scene& scene, Sampler& sampler, uint64_t& rays) const {
  return incidentRadiance(cameraRay, scene, sampler, rays, settings_.length.maxSegments(), true);
}

Color PathTracer::incidentRadiance(const Ray& cameraRay, const Scene& scene, Sampler& sampler, uint64_t& rays,
                                   int maxDepth, bool firstEmission, float* firstHitDistance) const {
  Color L(0.f), beta(1.f);
  Ray ray = cameraRay;
  float etaScale = 1;        // removes radiance's 1/η² scaling from roulette decisions
  bool prevDelta = true;     // the camera "bounce" is a delta event: emission counts in full
  float prevPdf = 0;         // solid-angle pdf of the direction that generated `ray`
  Vec3 prevPoint = ray.o;
  const LightSampler& lights = scene.lightSampler();
  if (firstHitDistance) *firstHitDistance = Infinity;

  for (int segments = 1; segments <= maxDepth; ++segments) {
    SurfaceInteraction si;
    ++rays;
    bool hit = scene.intersect(ray, si);
    if (segments == 1 && hit && firstHitDistance) *firstHitDistance = si.t;
    bool countEmission = segments > 1 || firstEmission;

    // Emission reached by this segment, MIS-weighted against NEE (Veach Eq. 9.13).
    auto emissionWeight = [&](const Light* light, float pdfLi) {
      if (prevDelta || !settings_.nee) return 1.f;
      if (settings_.mis == MisHeuristic::None) return 0.f;
      return misWeight(prevPdf, lights.pmf(light) * pdfLi);
    };
    if (!hit) {
      if (!countEmission) break;
      for (const Light* env : scene.infiniteLights()) {
        Color Le = env->Le(ray.d);
        if (!isBlack(Le)) L += beta * Le * emissionWeight(env, env->pdfLi(prevPoint, ray.d, {}, {}));
      }
      break;
    }
    if (si.emitter && countEmission) {
      Color Le = si.emitter->L(si.ng, si.wo);
      if (!isBlack(Le)) L += beta * Le * emissionWeight(si.emitter, si.emitter->pdfLi(prevPoint, ray.d, si.p, si.ng));
    }
    if (segments == maxDepth || !si.material) break;

    BSDF bsdf(si);
    bool delta = bsdf.isDelta();
    bool uniformOrCosine = settings_.sampling != DirectionSampling::Bsdf && !delta;

    // Next-event estimation: one light, one point on it.
    if (settings_.nee && !delta && !lights.empty()) {
      if (auto d = sampleDirectLight(scene, si, bsdf, sampler, rays)) {
        float scatterPdf = uniformOrCosine ? hemispherePdf(settings_.sampling, bsdf, si.wo, d->wi) : d->bsdfPdf;
        float w = d->deltaLight ? 1.f : misWeight(d->lightPdf, scatterPdf);
        L += beta * d->contribution * w;
      }
    }

    // Continue the path.
    float uLobe = sampler.get1D();
    Vec2 uDir = sampler.get2D();
    Vec3 wi;
    if (uniformOrCosine) {
      DirectionChoice d = sampleHemisphere(settings_.sampling, bsdf, si.wo, uLobe, uDir);
      BSDFEval e = bsdf.eval(si.wo, d.wi, TransportMode::Radiance);
      if (d.pdf == 0 || isBlack(e.f)) break;
      beta *= e.f * absDot(d.wi, bsdf.shadingNormal()) / d.pdf;
      if (glm::dot(d.wi, si.ng) * glm::dot(si.wo, si.ng) < 0) etaScale *= sqr(bsdf.material().relativeEta(bsdf.frame().toLocal(si.wo)));
      wi = d.wi;
      prevPdf = d.pdf;
      prevDelta = false;
    } else {
      auto bs = bsdf.sample(si.wo, uLobe, uDir, TransportMode::Radiance);
      if (!bs) break;
      beta *= bs->weight;
      if (bs->lobe & BSDFTransmission) etaScale *= sqr(bs->eta);
      wi = bs->wi;
      prevPdf = bs->pdf;
      prevDelta = bs->isDelta();
    }
    if (isBlack(beta)) break;
    prevPoint = si.p;
    ray = si.spawnRay(wi);

    if (!settings_.length.survivesRoulette(segments, beta, etaScale, sampler)) break;
  }
  return L;
}

}  // namespace lb
