#pragma once
// Direct lighting with optimal MIS weights (Kondapaneni et al. 2019; the
// weights and why this form is unbiased: optimal_mis.h). It estimates what
// `direct` does — the emitters seen directly, plus light from an emitter
// reflected once — from the same two samples per camera sample, a light
// sample and a BSDF sample, but combines them with coefficients α learned
// per pixel instead of a fixed heuristic:
//  * the camera sample's pixel solves A α = b from the sums of its earlier
//    samples (after `pilot_passes` of them; before, α = 0, the balance
//    heuristic), so each sample is unbiased given the ones before it;
//  * what only one technique can sample (a delta light, a delta lobe, an
//    emitter seen directly) is outside the combination, weight 1.
// The two techniques' densities are those of path space (a point on an
// emitter seen from the shading point): a light sample that is occluded has
// BSDF density 0 there (the BSDF sample would stop at the occluder), a BSDF
// sample that hits a surface no light sample can produce (a non-emitter, an
// emitter's back) has light density 0. That is what makes the densities
// the techniques' true densities, which the control variates need.
#include <memory>
#include <vector>
#include "core/params.h"
#include "integrators/direct_optimal/optimal_mis.h"
#include "integrators/integrator.h"

namespace lb {

struct DirectOptimalSettings {
  bool optimal = true;  // false: α = 0, the balance heuristic (the comparison's baseline)
  int pilotPasses = 4;  // samples of a pixel before its α is used
  static DirectOptimalSettings read(Params& p);
};

class DirectOptimal final : public PixelIntegrator {
 public:
  explicit DirectOptimal(DirectOptimalSettings s) : settings_(s) {}
  void preprocess(const Scene& scene, const Sampler& prototype) override;
  // A pixel's α comes from its earlier samples: chunks rendered apart would
  // each learn their own, the two half-images of adaptive sampling would
  // share theirs, and a sample cannot be re-run alone.
  std::string splitRefusal() const override { return "each pixel's α is learned from its earlier samples"; }
  std::string adaptiveRefusal() const override { return "each pixel's α is learned from its earlier samples"; }
  bool replaysSamples() const override { return false; }
  // The sums of pixel (x, y), for tests.
  const OptimalMisSums& pixelSums(int x, int y) const { return sums_[size_t(y) * width_ + x]; }

 protected:
  Color Li(const Ray&, const Scene&, Sampler&, uint64_t&) const override { return Color(0.f); }  // unused
  Color pixelLi(int x, int y, const Ray& ray, const Scene& scene, Sampler& sampler, uint64_t& rays) const override;

 private:
  DirectOptimalSettings settings_;
  int width_ = 0;
  // Per pixel, written only by the thread rendering the pixel's tile, in
  // sample order (pixel_tiles.h): the image does not depend on the threads.
  mutable std::vector<OptimalMisSums> sums_;
};

}  // namespace lb
