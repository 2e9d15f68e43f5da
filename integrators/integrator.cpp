#include "integrators/integrator.h"
#include <tbb/enumerable_thread_specific.h>
#include "integrators/pixel_tiles.h"

namespace lb {

Color PixelIntegrator::samplePixel(const Scene& scene, Sampler& sampler, int x, int y, uint64_t sample,
                                   uint64_t& rays) const {
  sampler.start(uint64_t(y) * scene.camera.width() + x, sample);
  Camera::FilmSample film = scene.camera.sampleFilm(x, y, sampler.get2D());  // the pixel filter (core/filter.h)
  return pixelLi(x, y, scene.camera.generateRay(film.raster), scene, sampler, rays) * film.weight;
}

void PixelIntegrator::renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass,
                                 PassStats& stats) {
  forEachPixel(film.width(), film.height(), prototype, stats, [&](int, int x, int y, Sampler& sampler, uint64_t& rays) {
    film.addSample(x, y, pass, samplePixel(scene, sampler, x, y, pass, rays));
  });
}

void PixelIntegrator::renderSamples(const Scene& scene, Film& even, const Sampler& evenPrototype, Film& odd,
                                    const Sampler& oddPrototype, const std::vector<uint32_t>& count,
                                    const std::vector<uint64_t>& first, PassStats& stats) {
  tbb::enumerable_thread_specific<std::unique_ptr<Sampler>> oddSamplers([&] { return oddPrototype.clone(); });
  forEachPixel(even.width(), even.height(), evenPrototype, stats,
               [&](int, int x, int y, Sampler& evenSampler, uint64_t& rays) {
                 size_t p = size_t(y) * size_t(even.width()) + size_t(x);
                 Sampler& oddSampler = *oddSamplers.local();
                 for (uint64_t s = first[p]; s < first[p] + count[p]; ++s) {
                   bool isEven = s % 2 == 0;
                   Color L = samplePixel(scene, isEven ? evenSampler : oddSampler, x, y, s / 2, rays);
                   (isEven ? even : odd).addSample(x, y, s / 2, L);
                 }
               });
}

std::optional<Color> PixelIntegrator::replaySample(const Scene& scene, const Sampler& prototype, int x, int y,
                                                   uint64_t sample) {
  auto sampler = prototype.clone();
  uint64_t rays = 0;
  return samplePixel(scene, *sampler, x, y, sample, rays);
}

}  // namespace lb
