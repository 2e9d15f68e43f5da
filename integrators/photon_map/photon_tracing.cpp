#include "integrators/photon_map/photon_tracing.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <atomic>
#include "core/bsdfs/bsdf.h"
#include "core/sampler.h"
#include "integrators/emission.h"

namespace lb {

NonSpecularHit traceToNonSpecular(const Scene& scene, Ray ray, Sampler& sampler, int maxDepth, uint64_t& rays) {
  NonSpecularHit hit;
  for (int depth = 0; depth < maxDepth; ++depth) {
    SurfaceInteraction si;
    ++rays;
    if (!scene.intersect(ray, si)) {
      for (const Light* env : scene.infiniteLights()) hit.emitted += hit.beta * env->Le(ray.d);
      break;
    }
    if (depth == 0) hit.firstHitDistance = si.t;
    if (si.emitter) hit.emitted += hit.beta * si.emitter->L(si.ng, si.wo);
    if (!si.material) break;
    if (!si.material->isDelta()) {
      hit.si = si;
      hit.segments = depth + 1;
      break;
    }
    Vec2 uDir = sampler.get2D();  // the direction's two dimensions, then the lobe's (core/sampler.h)
    float uLobe = sampler.get1D();
    auto bs = BSDF(si).sample(si.wo, uLobe, uDir, TransportMode::Radiance);
    if (!bs) break;
    hit.beta *= bs->weight;
    ray = si.spawnRay(bs->wi);
  }
  return hit;
}

uint64_t tracePhotons(const Scene& scene, uint64_t seed, uint64_t pass, size_t paths, int maxBounces,
                      const std::function<void(size_t, const PhotonHit&)>& visit, Progress* progress,
                      bool specularChainsOnly) {
  const LightSampler& lights = scene.lightSampler();
  if (lights.empty() || paths == 0) return 0;
  size_t chunks = (paths + PhotonPathsPerChunk - 1) / PhotonPathsPerChunk;
  std::atomic<uint64_t> totalRays{0};
  IndependentSampler prototype(hashValues(seed, 0x70686f746f6eULL));  // a stream apart from camera samples
  tbb::parallel_for(tbb::blocked_range<size_t>(0, chunks), [&](const tbb::blocked_range<size_t>& range) {
    IndependentSampler sampler = prototype;
    uint64_t rays = 0;
    for (size_t c = range.begin(); c != range.end(); ++c)
      for (size_t i = c * PhotonPathsPerChunk; i < std::min(paths, (c + 1) * PhotonPathsPerChunk); ++i) {
        sampler.start(i, pass);
        auto emitted = sampleEmission(scene, sampler);
        if (!emitted) continue;
        Color beta = emitted->beta;
        Ray ray = emitted->emission.ray;
        bool specularChain = true;
        for (int bounces = 0; bounces < maxBounces; ++bounces) {
          SurfaceInteraction si;
          ++rays;
          if (!scene.intersect(ray, si) || !si.material) break;
          BSDF bsdf(si);
          if (!bsdf.isDelta()) visit(c, {&si, si.wo, beta, bounces, specularChain && bounces > 0});
          Vec2 uDir = sampler.get2D();  // the direction's two dimensions, then the lobe's (core/sampler.h)
          float uLobe = sampler.get1D();
          auto bs = bsdf.sample(si.wo, uLobe, uDir, TransportMode::Importance);
          if (!bs) break;
          specularChain = specularChain && bs->isDelta();
          if (specularChainsOnly && !specularChain) break;
          float survive = std::min(1.f, maxComponent(bs->weight));
          if (sampler.get1D() >= survive) break;
          beta *= bs->weight / survive;
          ray = si.spawnRay(bs->wi);
        }
      }
    totalRays += rays;
    if (progress) progress->advance(double(std::min(paths, range.end() * PhotonPathsPerChunk) - range.begin() * PhotonPathsPerChunk));
  });
  return totalRays.load();
}

}  // namespace lb
