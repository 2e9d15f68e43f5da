#include "integrators/integrator.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace lb {

namespace {
constexpr int TileSize = 16;
}

Color PixelIntegrator::samplePixel(const Scene& scene, Sampler& sampler, int x, int y, uint64_t sample,
                                   uint64_t& rays) const {
  sampler.start(uint64_t(y) * scene.camera.width() + x, sample);
  Vec2 jitter = sampler.get2D();
  Ray ray = scene.camera.generateRay(Vec2(x, y) + jitter);
  return Li(ray, scene, sampler, rays);
}

void PixelIntegrator::renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass,
                                 PassStats& stats) {
  int tilesX = (film.width() + TileSize - 1) / TileSize, tilesY = (film.height() + TileSize - 1) / TileSize;
  tbb::parallel_for(tbb::blocked_range<int>(0, tilesX * tilesY), [&](const tbb::blocked_range<int>& range) {
    auto sampler = prototype.clone();
    uint64_t rays = 0;
    for (int tile = range.begin(); tile != range.end(); ++tile) {
      int x0 = (tile % tilesX) * TileSize, y0 = (tile / tilesX) * TileSize;
      for (int y = y0; y < std::min(y0 + TileSize, film.height()); ++y)
        for (int x = x0; x < std::min(x0 + TileSize, film.width()); ++x)
          film.addSample(x, y, pass, samplePixel(scene, *sampler, x, y, pass, rays));
    }
    stats.rays += rays;
  });
}

std::optional<Color> PixelIntegrator::replaySample(const Scene& scene, const Sampler& prototype, int x, int y,
                                                   uint64_t sample) {
  auto sampler = prototype.clone();
  uint64_t rays = 0;
  return samplePixel(scene, *sampler, x, y, sample, rays);
}

}  // namespace lb
