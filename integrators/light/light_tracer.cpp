#include "integrators/light/light_tracer.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include "core/bsdfs/bsdf.h"
#include "integrators/emission.h"

namespace lb {

LightTracerSettings LightTracerSettings::read(Params& p) {
  LightTracerSettings s;
  s.length = PathLength::read(p);
  p.checkUnused();
  return s;
}

namespace {
// Paths per work item: fixed, so the merge order does not depend on threads.
constexpr size_t PathsPerChunk = 1024;
}  // namespace

void LightTracer::renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass,
                             PassStats& stats) {
  size_t paths = size_t(film.width()) * film.height();
  size_t chunks = (paths + PathsPerChunk - 1) / PathsPerChunk;
  std::vector<std::vector<Splat>> splats(chunks);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, chunks), [&](const tbb::blocked_range<size_t>& range) {
    auto sampler = prototype.clone();
    uint64_t rays = 0;
    for (size_t c = range.begin(); c != range.end(); ++c)
      for (size_t i = c * PathsPerChunk; i < std::min(paths, (c + 1) * PathsPerChunk); ++i) {
        sampler->start(i, pass);
        tracePath(scene, *sampler, splats[c], rays);
      }
    stats.rays += rays;
  });
  PassImage image(film.width(), film.height(), &scene.camera.filter());
  for (const auto& chunk : splats)
    for (const Splat& s : chunk) image.splat(s.raster, s.value, pass, film);
  film.addPass(image);
}

void LightTracer::tracePath(const Scene& scene, Sampler& sampler, std::vector<Splat>& splats, uint64_t& rays) const {
  const Camera& camera = scene.camera;
  int maxDepth = settings_.length.maxSegments();
  if (maxDepth < 1) return;
  auto emitted = sampleEmission(scene, sampler);
  if (!emitted) return;
  const Light* light = emitted->light;
  const LightEmission* e = &emitted->emission;
  float pmf = emitted->pmf;

  // s = 1, t = 1: the point on an area light seen directly by the camera.
  if (!light->isDelta() && !light->isInfinite()) {
    if (auto c = camera.connect(e->p)) {
      Color Le = light->L(e->n, c->wi);
      float cos = absDot(e->n, c->wi);
      if (!isBlack(Le) && cos > 0) {
        ++rays;
        Vec3 from = offsetRayOrigin(e->p, e->pError, e->n, c->wi);
        if (!scene.occluded({from, c->pinhole - from, 1 - ShadowEpsilon}))
          splats.push_back({c->raster, Le * cos * (c->We / c->pdf) / (pmf * e->pdfPos)});
      }
    }
  }

  Color beta = emitted->beta;
  // Roulette on the throughput relative to the emitted one: the emitted flux
  // scales with the scene's area, and the decision must not.
  const float rouletteScale = maxComponent(beta) > 0 ? 1 / maxComponent(beta) : 1.f;
  Ray ray = e->ray;
  for (int segments = 1;; ++segments) {
    SurfaceInteraction si;
    ++rays;
    if (!scene.intersect(ray, si) || !si.material) break;
    BSDF bsdf(si);
    // Connect this vertex to the camera: a path of segments + 1 segments.
    if (!bsdf.isDelta() && segments + 1 <= maxDepth) {
      if (auto c = camera.connect(si.p)) {
        BSDFEval f = bsdf.eval(si.wo, c->wi, TransportMode::Importance);
        Color contribution = beta * f.f * absDot(c->wi, bsdf.shadingNormal()) * (c->We / c->pdf);
        if (!isBlack(contribution)) {
          ++rays;
          if (!scene.occluded(si.spawnRayTo(c->pinhole, Vec3(0.f), Vec3(0.f))))
            splats.push_back({c->raster, contribution});
        }
      }
    }
    if (segments + 1 > maxDepth) break;  // no longer path can reach the camera
    Vec2 uDir = sampler.get2D();  // the direction's two dimensions, then the lobe's (core/sampler.h)
    float uLobe = sampler.get1D();
    auto bs = bsdf.sample(si.wo, uLobe, uDir, TransportMode::Importance);
    if (!bs) break;
    beta *= bs->weight;
    if (isBlack(beta)) break;
    ray = si.spawnRay(bs->wi);
    if (settings_.length.russianRoulette && segments >= settings_.length.rrDepth) {
      float survive = std::min(1.f, maxComponent(beta) * rouletteScale);
      if (sampler.get1D() >= survive) break;
      beta /= survive;
    }
  }
}

}  // namespace lb
