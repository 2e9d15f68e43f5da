#include "core/aov.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include "core/bsdfs/bsdf.h"
#include "core/sampler.h"

namespace lb {

FirstHitImages renderFirstHitImages(const Scene& scene, int samples, uint64_t seed) {
  const Camera& cam = scene.camera;
  int w = cam.width(), h = cam.height();
  FirstHitImages out{Image(w, h), Image(w, h), Image(w, h)};
  // Rows are independent; each pixel's random numbers depend only on (seed, pixel, sample).
  tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
    IndependentSampler sampler(hashValues(seed, 0xa0u));
    for (int y = rows.begin(); y != rows.end(); ++y)
      for (int x = 0; x < w; ++x) {
        Color albedo(0.f), normal(0.f);
        double depth = 0;
        int hits = 0;
        for (int s = 0; s < samples; ++s) {
          sampler.start(uint64_t(y) * w + x, uint64_t(s));
          Ray ray = cam.generateRay(Vec2(float(x), float(y)) + sampler.get2D());
          SurfaceInteraction si;
          if (!scene.intersect(ray, si)) continue;
          ++hits;
          depth += si.t;
          normal += si.shading.n;
          if (!si.material) continue;  // an emitter-only surface reflects nothing
          float uLobe = sampler.get1D();
          albedo += BSDF(si).albedoSample(si.wo, uLobe, sampler.get2D());
        }
        out.albedo.at(x, y) = albedo / float(samples);
        out.normal.at(x, y) = normal / float(samples);
        // The mean distance of the rays that hit.
        out.depth.at(x, y) = Color(hits ? float(depth / hits) : 0.f);
      }
  });
  return out;
}

}  // namespace lb
