#pragma once
// The one interface every integrator implements. The render loop
// (render_loop.h) calls preprocess() once, then renderPass() for pass 0, 1, 2…;
// each pass adds one sample per pixel (or, for light tracing, one light path per
// pixel) and must depend only on (seed, pass), never on thread scheduling.
#include <atomic>
#include <optional>
#include <string>
#include <vector>
#include "core/film.h"
#include "core/image.h"
#include "core/sampler.h"
#include "core/scene.h"

namespace lb {

struct PassStats {
  std::atomic<uint64_t> rays{0};
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  // Whether preprocess() may print a progress line (core/progress.h): the
  // render loop passes on its own setting.
  void setProgress(bool on) { progress_ = on; }
  // Work done once before sampling (photon maps, caches). Counted in a budget.
  virtual void preprocess(const Scene&, const Sampler& /*prototype*/) {}
  virtual void renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass,
                          PassStats& stats) = 0;
  // Extra images an integrator can write beside the main one (photon
  // densities, cache records); returns the paths written.
  virtual std::vector<std::string> writeExtraOutputs(const std::string& /*stem*/) const { return {}; }
  // Every file writeExtraOutputs(stem) may write, known from the settings
  // before rendering: the render command checks them first (a directory in
  // the way would otherwise be found after the whole render).
  virtual std::vector<std::string> extraOutputPaths(const std::string& /*stem*/) const { return {}; }
  // False for estimators whose passes are correlated (MLT's chains): their
  // spread over passes is no error estimate, so no variance layer is written.
  virtual bool independentPasses() const { return true; }
  // Why a render of N passes cannot be split exactly into independent
  // chunks of passes with their own seeds, averaged (`lightbench render
  // --distributed`, experiments/chunks.h), or "" if it can: the chunks' mean
  // must estimate what one render does, with the same bias.
  virtual std::string splitRefusal() const { return "its passes are not independent"; }
  // Lines for the render's summary about the integrator's own estimates
  // (MLT's normalisation constant and acceptance rates).
  virtual std::vector<std::string> summaryLines() const { return {}; }
  // Images that belong in the main EXR as layers (BDPT's per-strategy images).
  virtual std::vector<ExrLayer> extraLayers() const { return {}; }
  // Why adaptive sampling (adaptive_sampling.h) cannot drive this
  // integrator, or "" if it can: it needs each pixel estimated from its own
  // camera samples, with nothing learned from a pass as a whole.
  virtual std::string adaptiveRefusal() const { return "it does not estimate each pixel from its own camera samples"; }
  // Re-runs one camera sample (pixel, sample index) for debugging, if the
  // integrator estimates pixels one at a time (replaysSamples()).
  virtual bool replaysSamples() const { return false; }
  virtual std::optional<Color> replaySample(const Scene&, const Sampler&, int /*x*/, int /*y*/, uint64_t /*sample*/) {
    return std::nullopt;
  }

 protected:
  bool progress_ = false;
};

// Base for integrators that estimate each pixel independently from camera rays
// (path tracing, photon mapping's gather, irradiance caching).
class PixelIntegrator : public Integrator {
 public:
  void renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass, PassStats& stats) override;
  std::string adaptiveRefusal() const override { return ""; }
  // Adaptive sampling: count[p] camera samples of pixel p (p = y·width + x),
  // numbered first[p], first[p] + 1, …; sample s goes to `even` if s is
  // even, else to `odd`, as that film's sample s/2, drawing its numbers
  // from the matching prototype.
  void renderSamples(const Scene& scene, Film& even, const Sampler& evenPrototype, Film& odd,
                     const Sampler& oddPrototype, const std::vector<uint32_t>& count,
                     const std::vector<uint64_t>& first, PassStats& stats);
  bool replaysSamples() const override { return true; }
  std::optional<Color> replaySample(const Scene& scene, const Sampler& prototype, int x, int y, uint64_t sample) override;

 protected:
  // Radiance arriving along `ray`; `rays` counts the rays traced.
  virtual Color Li(const Ray& ray, const Scene& scene, Sampler& sampler, uint64_t& rays) const = 0;
  // The same for a camera sample of pixel (x, y): for an estimator that
  // keeps something per pixel (path's variance-aware MIS); by default Li().
  virtual Color pixelLi(int /*x*/, int /*y*/, const Ray& ray, const Scene& scene, Sampler& sampler,
                        uint64_t& rays) const {
    return Li(ray, scene, sampler, rays);
  }

 private:
  Color samplePixel(const Scene& scene, Sampler& sampler, int x, int y, uint64_t sample, uint64_t& rays) const;
};

}  // namespace lb
