#include "integrators/path/path_tracer.h"
#include "integrators/path/wavefront.h"

namespace lb {

PathTracer::PathTracer(PathTracerSettings s) : estimator_(s) {
  if (s.wavefront) wavefront_ = std::make_unique<WavefrontEngine>(estimator_);
}

PathTracer::~PathTracer() = default;

void PathTracer::renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass, PassStats& stats) {
  if (wavefront_) return wavefront_->renderPass(scene, film, prototype, pass, stats);
  PixelIntegrator::renderPass(scene, film, prototype, pass, stats);
  // Variance-aware MIS learns between passes only, so every pass's image
  // is the same whatever the thread count.
  const PathTracerSettings& s = estimator_.settings();
  if (varianceAware_ && !varianceAware_->finished() && ++pilotPassesDone_ == s.pilotPasses)
    varianceAware_->finish(s.pilotPasses, s.shadowRays);
}

Color PathTracer::pixelLi(int x, int y, const Ray& ray, const Scene& scene, Sampler& sampler, uint64_t& rays) const {
  if (!varianceAware_) return estimator_.Li(ray, scene, sampler, rays);
  VarianceAwareView view{varianceAware_.get(), x, y, !varianceAware_->finished()};
  return estimator_.Li(ray, scene, sampler, rays, &view);
}

void PathTracer::preprocess(const Scene& scene, const Sampler& prototype) {
  estimator_.preprocess(scene, prototype.seed());
  const PathTracerSettings& s = estimator_.settings();
  if (s.mis == MisHeuristic::VarianceAware) {
    varianceAware_ = std::make_unique<VarianceAwareMis>(scene.camera.width(), scene.camera.height(), s.factorBlock);
    pilotPassesDone_ = 0;
  }
}

}  // namespace lb
