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
}

void PathTracer::preprocess(const Scene& scene, const Sampler& prototype) {
  estimator_.preprocess(scene, prototype.seed());
}

}  // namespace lb
