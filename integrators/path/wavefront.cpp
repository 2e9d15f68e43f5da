#include "integrators/path/wavefront.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include "core/bsdfs/bsdf.h"

namespace lb {

void WavefrontEngine::renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass,
                                 PassStats& stats) {
  const int W = film.width(), H = film.height();
  const int across = (W + BatchSize - 1) / BatchSize, down = (H + BatchSize - 1) / BatchSize;
  tbb::parallel_for(tbb::blocked_range<int>(0, across * down, 1), [&](const tbb::blocked_range<int>& range) {
    Workspace& w = workspaces_.local();
    w.sampler = prototype.clone();  // this pass's prototype (a render may change seeds)
    uint64_t rays = 0;
    for (int b = range.begin(); b != range.end(); ++b) {
      int x0 = (b % across) * BatchSize, y0 = (b / across) * BatchSize;
      rays += renderBatch(w, scene, film, pass, x0, y0, std::min(W, x0 + BatchSize), std::min(H, y0 + BatchSize));
    }
    stats.rays += rays;
  });
}

uint64_t WavefrontEngine::renderBatch(Workspace& w, const Scene& scene, Film& film, uint64_t pass, int x0, int y0,
                                      int x1, int y1) const {
  const size_t n = size_t(x1 - x0) * size_t(y1 - y0);
  const int shadowsPerPath = estimator_.settings().shadowRays;
  const int maxDepth = estimator_.settings().length.maxSegments();
  const Camera& camera = scene.camera;
  Sampler& sampler = *w.sampler;
  // Sized once per workspace; later batches reuse the storage.
  w.paths.resize(n), w.L.assign(n, Color(0.f)), w.filterWeight.resize(n), w.pixel.resize(n), w.rayhits.resize(n);
  w.shadows.resize(n * size_t(shadowsPerPath)), w.shadowOwner.resize(n * size_t(shadowsPerPath));
  w.shadowRays.resize(n * size_t(shadowsPerPath));
  w.active.clear();
  if (maxDepth < 1) {  // max_depth 0 renders black
    for (size_t i = 0; i < n; ++i) film.addSample(x0 + int(i) % (x1 - x0), y0 + int(i) / (x1 - x0), pass, Color(0.f));
    return 0;
  }

  // Camera rays: dimensions 0-1 are the pixel jitter, as in PixelIntegrator.
  for (size_t i = 0; i < n; ++i) {
    int x = x0 + int(i % size_t(x1 - x0)), y = y0 + int(i / size_t(x1 - x0));
    w.pixel[i] = uint64_t(y) * uint64_t(camera.width()) + uint64_t(x);
    sampler.start(w.pixel[i], pass);
    Camera::FilmSample at = camera.sampleFilm(x, y, sampler.get2D());
    w.filterWeight[i] = at.weight;
    PathState& s = w.paths[i];
    s = PathState();
    s.ray = camera.generateRay(at.raster);
    s.prevPoint = s.ray.o;
    w.active.push_back(int(i));
  }

  uint64_t rays = 0;
  for (bool coherent = true; !w.active.empty(); coherent = false) {
    // (1) The extension rays of every live path, as one stream.
    const size_t live = w.active.size();
    for (size_t k = 0; k < live; ++k) Scene::toEmbree(w.paths[size_t(w.active[k])].ray, w.rayhits[k]);
    scene.intersect1M(w.rayhits.data(), live, coherent);
    rays += live;

    // (2) Shade in order; survivors are packed into nextActive.
    size_t queued = 0;
    w.nextActive.clear();
    for (size_t k = 0; k < live; ++k) {
      const int i = w.active[k];
      PathState& s = w.paths[size_t(i)];
      sampler.start(w.pixel[size_t(i)], pass);
      PathContext ctx{scene, sampler, maxDepth, true, 2};
      SurfaceInteraction si;
      bool hit = scene.interaction(s.ray, w.rayhits[k], si);
      std::optional<BSDF> bsdf;
      int made = estimator_.shadeVertex(s, hit, si, ctx, w.L[size_t(i)], &w.shadows[queued], bsdf);
      for (int j = 0; j < made; ++j) w.shadowOwner[queued + size_t(j)] = i;
      queued += size_t(made);
      if (!bsdf) continue;
      if (!estimator_.scatter(s, si, *bsdf, sampler, estimator_.vertexBase(s, ctx))) continue;
      ++s.vertex;
      w.nextActive.push_back(i);
    }

    // (3) The bounce's light samples, as one occlusion stream.
    for (size_t k = 0; k < queued; ++k) Scene::toEmbree(w.shadows[k].ray, w.shadowRays[k]);
    scene.occluded1M(w.shadowRays.data(), queued, false);
    rays += queued;
    for (size_t k = 0; k < queued; ++k)
      if (!(w.shadowRays[k].tfar < 0)) w.L[size_t(w.shadowOwner[k])] += w.shadows[k].contribution;
    std::swap(w.active, w.nextActive);
  }

  for (size_t i = 0; i < n; ++i)
    film.addSample(x0 + int(i % size_t(x1 - x0)), y0 + int(i / size_t(x1 - x0)), pass, w.L[i] * w.filterWeight[i]);
  return rays;
}

}  // namespace lb
