// Camera and light subpaths (subpaths.h; pbrt-v3 §16.3.2 with Russian roulette).
#include "integrators/bidirectional/subpaths.h"
#include "integrators/emission.h"

namespace lb::bidir {

namespace {

// Extends `path` from index `start` (whose vertex is path[start - 1]) by
// sampling the BSDF at each hit; returns the number of vertices added.
int randomWalk(const Scene& scene, Sampler& sampler, const PathLength& s, Ray ray, Color beta, float pdfFwd,
               int maxVertices, TransportMode mode, std::vector<Vertex>& path, int start, uint64_t& rays,
               const WalkDimensions& dims, WalkStop stop, const Regularization* regularization) {
  const float startThroughput = maxComponent(beta);
  const float rouletteScale = startThroughput > 0 ? 1 / startThroughput : 1.f;
  if (maxVertices <= 0) return 0;
  int added = 0;
  float etaScale = 1;
  // regularize (core/bsdfs/regularization.h): a light walk mollifies every
  // delta vertex, a camera walk those after its first non-delta one.
  bool pastNonDelta = mode == TransportMode::Importance;
  while (true) {
    SurfaceInteraction si;
    ++rays;
    Vertex& prev = path[size_t(start + added - 1)];
    if (!scene.intersect(ray, si)) {
      // An escaped camera ray is a vertex on the environment (strategy s = 0).
      if (mode == TransportMode::Radiance && !scene.infiniteLights().empty()) {
        path[size_t(start + added)] = escapedVertex(ray, beta, pdfFwd);
        ++added;
      }
      break;
    }
    Vertex& v = path[size_t(start + added)];
    v = surfaceVertex(si, beta);
    v.pdfFwd = convertDensity(prev, pdfFwd, v);
    if (regularization && si.material) {
      if (pastNonDelta)
        if (const Material* twin = regularization->twin(si.material)) {
          si.material = v.si.material = twin;  // every later use of this vertex sees the twin
          v.regularized = true;
        }
      pastNonDelta = pastNonDelta || !si.material->isDelta();
    }
    ++added;
    if (added >= maxVertices || !si.material) break;
    if (stop == WalkStop::AtFirstNonSpecular && v.mergeable()) break;
    BSDF bsdf(si);
    if (dims.stride > 0) sampler.setDimension(dims.first + dims.stride * uint32_t(start + added - 2));
    Vec2 uDir = sampler.get2D();  // the direction's two dimensions, then the lobe's (core/sampler.h)
    float uLobe = sampler.get1D();
    auto bs = bsdf.sample(si.wo, uLobe, uDir, mode);
    if (!bs) break;
    beta *= bs->weight;
    // A delta lobe keeps its discrete probability as its density (vertex.h):
    // the next vertex's area density still carries |cos|/d² of this segment,
    // so that a specular chain's geometry cancels between strategies.
    // Through a smooth refraction the reverse density carries the Jacobian
    // of the refraction map (vertex.h).
    float pdfRev = reverseDirectionalDensity(si, *bs);
    pdfFwd = bs->pdf;
    v.delta = bs->isDelta();
    prev.pdfRev = convertDensity(v, pdfRev, prev);
    if (isBlack(beta)) break;
    if (mode == TransportMode::Radiance && (bs->lobe & BSDFTransmission)) etaScale *= sqr(bs->eta);
    ray = si.spawnRay(bs->wi);
    // Roulette after rr_depth segments of this subpath; not part of the MIS pdfs (vertex.h).
    // The throughput is taken relative to the walk's starting one: a light
    // subpath starts with the emitted flux, which scales with the scene's
    // area, and the decision must not depend on the scene's scale.
    if (s.russianRoulette && start + added - 1 >= s.rrDepth) {
      float survive = std::min(1.f, maxComponent(beta) * etaScale * rouletteScale);
      if (sampler.get1D() >= survive) break;
      beta /= survive;
    }
  }
  return added;
}

int maxSegments(const PathLength& s) { return s.maxSegments(); }

}  // namespace

int generateCameraSubpath(const Scene& scene, Sampler& sampler, const PathLength& s, Vec2 raster,
                          std::vector<Vertex>& path, uint64_t& rays, const WalkDimensions& dims, WalkStop stop,
                          const Regularization* regularization) {
  if (maxSegments(s) < 1) return 0;
  Ray ray = scene.camera.generateRay(raster);
  path[0] = cameraVertex(scene.camera, Color(1.f));
  float pdfPos, pdfDir;
  scene.camera.pdfWe(ray.d, &pdfPos, &pdfDir);
  // Up to max_depth segments: the camera plus max_depth vertices (and never
  // past the caller's array, which caps "unlimited" depth).
  int room = int(path.size()) - 1;
  return 1 + randomWalk(scene, sampler, s, ray, Color(1.f), pdfDir, std::min(maxSegments(s), room),
                        TransportMode::Radiance, path, 1, rays, dims, stop, regularization);
}

int generateLightSubpath(const Scene& scene, Sampler& sampler, const PathLength& s, std::vector<Vertex>& path,
                         uint64_t& rays, const WalkDimensions& dims, const Regularization* regularization) {
  if (maxSegments(s) < 1) return 0;
  if (dims.stride > 0) sampler.setDimension(dims.emission);
  auto emitted = sampleEmission(scene, sampler);
  if (!emitted) return 0;
  const Light* light = emitted->light;
  const LightEmission* e = &emitted->emission;
  path[0] = lightVertex(light, e->p, e->n, e->pError, e->Le, e->pdfPos * emitted->pmf);
  Color beta = emitted->beta;
  // The light subpath needs at most max_depth vertices (s + t - 1 <= max_depth with t >= 1).
  int n = 1 + randomWalk(scene, sampler, s, e->ray, beta, e->pdfDir, std::min(maxSegments(s) - 1, int(path.size()) - 1),
                         TransportMode::Importance, path, 1, rays, dims, WalkStop::AtLength, regularization);
  if (light->isInfinite()) {
    // Lights at infinity: the first hit's density is the disc's (per area),
    // and the light vertex's own density is per solid angle (pbrt-v3).
    if (n > 1) {
      path[1].pdfFwd = e->pdfPos;
      if (path[1].onSurface()) path[1].pdfFwd *= absDot(e->ray.d, path[1].ng);
    }
    path[0].pdfFwd = pdfLightOrigin(scene, path[0], n > 1 ? path[1] : path[0]);
  }
  return n;
}

}  // namespace lb::bidir
