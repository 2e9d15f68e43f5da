#pragma once
// The `path` integrator: unidirectional path tracing with the switches of the
// classic comparisons. The estimator itself (its keys, the estimators it
// implements and its sampler-dimension layout) is documented in
// integrators/path_estimator/path_estimator.h, where it is shared with the
// irradiance cache and primary-sample-space MLT; this is the integrator
// around it: one camera path per pixel and pass, traced one ray at a time or
// by the wavefront engine (wavefront.h).
#include <memory>
#include "integrators/integrator.h"
#include "integrators/path_estimator/path_estimator.h"

namespace lb {

class PathTracer final : public PixelIntegrator {
 public:
  // Unbiased with independent passes: chunks of passes split a render exactly
  // (not a regularized one, whose roughness depends on the pass).
  std::string splitRefusal() const override {
    return estimator_.settings().regularization.enabled ? "regularize: its roughness follows the passes' count" : "";
  }
  explicit PathTracer(PathTracerSettings s);
  ~PathTracer() override;
  void preprocess(const Scene& scene, const Sampler& prototype) override;
  void renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass, PassStats& stats) override;
  // Adaptive sampling runs pixel by pixel, on the single-ray engine.
  std::string adaptiveRefusal() const override {
    if (wavefront_) return "engine: wavefront traces whole passes; use engine: single_ray";
    if (estimator_.settings().mis == MisHeuristic::VarianceAware)
      return "mis: variance_aware learns its factors from whole passes";
    if (estimator_.settings().rrs != RrsMethod::Classic) return "rrs: adrrs and ears learn from whole passes";
    if (estimator_.settings().regularization.enabled) return "regularize: its roughness shrinks pass by pass";
    return "";
  }
  // A learning estimator's sample depends on every pass before it; a
  // regularized one on its pass's roughness.
  bool replaysSamples() const override {
    const PathTracerSettings& s = estimator_.settings();
    return s.mis != MisHeuristic::VarianceAware && s.rrs == RrsMethod::Classic && !s.regularization.enabled;
  }
  const PathEstimator& estimator() const { return estimator_; }

 protected:
  Color Li(const Ray& ray, const Scene& scene, Sampler& sampler, uint64_t& rays) const override {
    return estimator_.Li(ray, scene, sampler, rays);
  }
  Color pixelLi(int x, int y, const Ray& ray, const Scene& scene, Sampler& sampler, uint64_t& rays) const override;

 private:
  PathEstimator estimator_;
  std::unique_ptr<class WavefrontEngine> wavefront_;  // engine: wavefront
  // mis: variance_aware: the factors, learned in the first pilot_passes
  // passes this integrator renders (variance_aware_mis.h).
  std::unique_ptr<VarianceAwareMis> varianceAware_;
  int pilotPassesDone_ = 0;
  // rrs: adrrs | ears: the continuations' cache and the pixel estimates,
  // both updated after every pass (roulette_splitting.h).
  std::unique_ptr<RrsLearning> rrs_;
  // regularize: the scene's rough twins for the pass being rendered.
  std::unique_ptr<Regularization> regularization_;
};

}  // namespace lb
