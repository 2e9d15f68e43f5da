#pragma once
// The `guided` integrator: the path tracer (integrators/path_estimator/) with
// directions drawn from a learned distribution mixed with the BSDF
// (direction_guide.h), learned by one of two methods:
//
//   method: qlearning   Dahm & Keller 2017 (q_learning.h): a grid of cells,
//                       each with Q-values over a discretised sphere, updated
//                       toward the Bellman target after every pass; every pass
//                       counts in the image (learning and rendering at once).
//   method: sdtree      Müller, Gross, Novák 2017 (sd_tree.h): an SD-tree
//                       trained in iterations of 1, 2, 4, … spp during the
//                       preprocess (counted in the time budget); the image is
//                       rendered with the last iteration's trees, frozen.
//
//   bsdf_fraction c     the mixture's BSDF share, in (0, 1]: the guide draws
//                       with probability 1 − c (0.5, as Müller et al. use)
//   debug_point "x,y"   writes <output>_guide.exr/.png: the learned density
//                       over directions (φ across, cos θ down, sphere_map.h)
//                       at the surface seen through pixel (x, y)
// and the path tracer's keys (nee, mis, shadow_rays, light_selection,
// max_depth, rr, rrs, …), except those that change how directions are drawn
// (sampling, first_bounce_samples and engine are not accepted).
//
// rrs: adrrs | ears (learned roulette and splitting, roulette_splitting.h)
// learn from every pass, the SD-tree's training passes included, and so
// need the independent sampler, as Q-learning does. A split's continuations
// all draw their directions from the guide before any is traced
// (path_splitting.cpp), and the recorder credits each vertex with its own
// subtree only (vertex_recorder.h).
//
// Unbiasedness: a pass samples a distribution fixed before it starts, and
// every direction's weight uses the mixture's exact density, positive
// wherever the BSDF's is (c > 0), so each pass is an unbiased estimate.
// Training paths use their own random stream (an independent sampler seeded
// from the run's seed), so the final image's samples are independent of what
// the trees learned from. (With Q-learning the passes themselves teach the
// next; their numbers are independent only under the independent sampler,
// which Q-learning therefore requires. Replaying one of its samples, with
// --pixel, uses the table as the render left it, not as that pass saw it.)
//
// Determinism: paths record their vertices into per-tile lists, learned from
// after the pass in tile order (guiding_method.h): the same image for a seed
// whatever the thread count.
#include <tbb/enumerable_thread_specific.h>

#include <memory>
#include <optional>
#include "integrators/guided/guiding_method.h"
#include "integrators/guided/q_learning.h"
#include "integrators/guided/sd_tree.h"
#include "integrators/integrator.h"
#include "integrators/path_estimator/path_estimator.h"

namespace lb {

struct GuidedSettings {
  enum class Method { QLearning, SdTree } method = Method::SdTree;
  float bsdfFraction = 0.5f;
  guiding::QLearningSettings qlearning;
  guiding::SdTreeSettings sdtree;
  std::optional<std::pair<int, int>> debugPoint;
  PathTracerSettings path;
  static GuidedSettings read(Params& p);
};

class GuidedPathTracer final : public PixelIntegrator {
 public:
  std::string splitRefusal() const override {
    return "it learns from earlier passes; each chunk would learn from its own passes only";
  }
  explicit GuidedPathTracer(GuidedSettings s);
  void preprocess(const Scene& scene, const Sampler& prototype) override;
  void renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass, PassStats& stats) override;
  std::vector<std::string> summaryLines() const override;
  std::vector<std::string> extraOutputPaths(const std::string& stem) const override;
  std::vector<std::string> writeExtraOutputs(const std::string& stem) const override;
  // Q-learning learns from whole passes; the SD-tree is fixed after training.
  std::string adaptiveRefusal() const override {
    if (settings_.method == GuidedSettings::Method::QLearning) return "guided's method: qlearning learns from whole passes";
    if (settings_.path.rrs != RrsMethod::Classic) return "rrs: adrrs and ears learn from whole passes";
    return "";
  }
  // With rrs: adrrs | ears a sample depends on every pass before it.
  bool replaysSamples() const override { return settings_.path.rrs == RrsMethod::Classic; }
  const guiding::GuidingMethod& method() const { return *method_; }

 protected:
  Color Li(const Ray& ray, const Scene& scene, Sampler& sampler, uint64_t& rays) const override;

 private:
  // One camera path; with `records`, its scattering vertices are appended.
  Color trace(const Ray& ray, const Scene& scene, Sampler& sampler, DirectionGuide& guide,
              std::vector<guiding::GuideVertex>* records, uint64_t& rays, const RrsView* rrs = nullptr) const;
  // Every pixel once (sample index `pass`); with `learn`, the method learns from the paths afterwards.
  void pass(const Scene& scene, Film& film, const Sampler& sampler, uint64_t pass, PassStats& stats, bool learn);

  GuidedSettings settings_;
  PathEstimator estimator_;
  std::unique_ptr<guiding::GuidingMethod> method_;
  // Each thread's view of method_ (made again after each preprocess).
  DirectionGuide& localGuide() const;
  mutable tbb::enumerable_thread_specific<std::unique_ptr<DirectionGuide>> guides_;
  // rrs: adrrs | ears: the cache and the pixel estimates (roulette_splitting.h).
  std::unique_ptr<RrsLearning> rrs_;
  const Scene* scene_ = nullptr;
  uint64_t trainingPasses_ = 0;
  double trainingSeconds_ = 0;
};

}  // namespace lb
