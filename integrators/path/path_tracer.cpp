#include "integrators/path/path_tracer.h"
#include "integrators/path/wavefront.h"
#include <stdexcept>

namespace lb {

PathTracer::PathTracer(PathTracerSettings s) : estimator_(s) {
  if (s.wavefront) wavefront_ = std::make_unique<WavefrontEngine>(estimator_);
}

PathTracer::~PathTracer() = default;

void PathTracer::renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass, PassStats& stats) {
  if (wavefront_) return wavefront_->renderPass(scene, film, prototype, pass, stats);
  if (regularization_) regularization_->prepare(scene, pass);  // this pass's roughness, fixed while it renders
  PixelIntegrator::renderPass(scene, film, prototype, pass, stats);
  // Variance-aware MIS learns between passes only, so every pass's image
  // is the same whatever the thread count.
  const PathTracerSettings& s = estimator_.settings();
  if (varianceAware_ && !varianceAware_->finished() && ++pilotPassesDone_ == s.pilotPasses)
    varianceAware_->finish(s.pilotPasses, s.shadowRays);
  if (rrs_) rrs_->endPass();
}

Color PathTracer::pixelLi(int x, int y, const Ray& ray, const Scene& scene, Sampler& sampler, uint64_t& rays) const {
  if (rrs_) {
    RrsView view = rrs_->view(x, y);
    const uint64_t raysBefore = rays;
    Color L = estimator_.Li(ray, scene, sampler, rays, nullptr, &view, regularization_.get());
    rrs_->recordPixel(x, y, L, double(rays - raysBefore));
    return L;
  }
  if (!varianceAware_) return estimator_.Li(ray, scene, sampler, rays, nullptr, nullptr, regularization_.get());
  VarianceAwareView view{varianceAware_.get(), x, y, !varianceAware_->finished()};
  return estimator_.Li(ray, scene, sampler, rays, &view);
}

void PathTracer::preprocess(const Scene& scene, const Sampler& prototype) {
  estimator_.preprocess(scene, prototype.seed());
  const PathTracerSettings& s = estimator_.settings();
  // A learned state is a function of the earlier passes' numbers; a pass
  // is unbiased under it only if its own numbers are independent of theirs,
  // which a low-discrepancy sequence's are not (as guided's Q-learning).
  bool learns = s.mis == MisHeuristic::VarianceAware || s.rrs != RrsMethod::Classic;
  if (learns && !dynamic_cast<const IndependentSampler*>(&prototype))
    throw std::invalid_argument(
        "path, mis: variance_aware or rrs: adrrs | ears: each pass uses what the earlier passes learned, so their "
        "random numbers must be independent: use sampler type independent");
  if (s.mis == MisHeuristic::VarianceAware) {
    varianceAware_ = std::make_unique<VarianceAwareMis>(scene.camera.width(), scene.camera.height(), s.factorBlock);
    pilotPassesDone_ = 0;
  }
  if (s.regularization.enabled) regularization_ = std::make_unique<Regularization>(s.regularization);
  if (s.rrs != RrsMethod::Classic)
    rrs_ = std::make_unique<RrsLearning>(s.rrs, s.rrsWarmup, scene.bounds(), s.rrsCells, s.rrsMinSamples,
                                         scene.camera.width(), scene.camera.height());
}

}  // namespace lb
