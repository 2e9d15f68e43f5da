#pragma once
// Metropolis light transport in primary sample space (`mlt`):
//
//   mode: pssmlt   Kelemen, Szirmay-Kalos, Antal, Csonka 2002: Markov chains
//                  over the uniform numbers of a path tracer (base: path) or
//                  of one BDPT sample with all its strategies (base: bdpt).
//   mode: mmlt     Hachisuka, Kaplanyan, Dachsbacher 2014, multiplexed MLT:
//                  the primary sample also picks the path length and one
//                  (s, t) strategy, whose MIS-weighted contribution is the
//                  chain's target (integrands.h), using the bidirectional
//                  module's subpaths, connections and MIS weights.
//
// The machinery is metropolis.h (bootstrap, chains, expected-value splats)
// over primary_sample.h (the state and its mutations):
//   large_step_probability  0.3      chance that a mutation is a large step
//   sigma                   1/64     Kelemen's largest small-step offset s2 (s1 = s2/16)
//   bootstrap_samples       100000   independent samples that estimate b = ∫ f
//                                    and choose the chains' starts (counted in
//                                    the time budget: they are the preprocess)
//   chains                  64       Markov chains, each started at a bootstrap
//                                    sample chosen in proportion to f
//   max_depth, rr, rr_depth          path length (path_length.h); mmlt needs a
//                                    finite max_depth and builds each strategy's
//                                    subpaths to their chosen length, without
//                                    roulette (rr, rr_depth apply to pssmlt only)
//   mis                     power    BDPT's heuristic (base: bdpt, mmlt)
//   length_selection        pilot    mmlt: how the control picks the path length k:
//                                    uniform in [1, max_depth], or (pilot) in
//                                    proportion to each length's share of b in a
//                                    pilot of bootstrap_samples/4 uniform-length
//                                    samples, mixed 9:1 with uniform so that every
//                                    length keeps a positive probability (the
//                                    image stays unbiased: p(k) is fixed before
//                                    the bootstrap and the chains). Uniform wastes
//                                    most samples on lengths that carry little
//                                    light (on the Cornell box, 91 % of them were
//                                    zero at max_depth 32); pbrt-v3 reaches the
//                                    same end by giving each length its own chains.
//
// Budgets: a pass is one mutation per pixel (width × height mutations shared
// among the chains), so --spp counts mutations per pixel and --time stops
// between passes as for every integrator. The scene's sampler is not used:
// the chains draw their own numbers.
//
// Determinism: every chain has its own random streams (seed, chain index)
// and a fixed share of each pass's mutations, and the splats are added in
// chain order, so the image is the same bit for bit for a seed, whatever the
// thread count (tested). The number of chains is a setting, not the number of
// threads, for that reason.
//
// Variance: successive passes of a chain are correlated, so the film's
// per-pixel variance over passes is not an estimate of the error; the film
// reports it as unknown (NaN in the experiment log). Error bars for MLT come
// from independent runs (different seeds).
#include <memory>
#include <string>
#include <vector>
#include "core/params.h"
#include "integrators/bidirectional/connect.h"
#include "integrators/integrator.h"
#include "integrators/mlt/metropolis.h"
#include "integrators/path_length.h"

namespace lb {

class PathEstimator;

struct MltSettings {
  enum class Mode { Pssmlt, Mmlt } mode = Mode::Pssmlt;
  enum class Base { Path, Bdpt } base = Base::Path;
  PathLength length;
  bidir::MisWeighting mis = bidir::MisWeighting::Power;
  mlt::MetropolisSettings metropolis;
  uint64_t bootstrapSamples = 100000;
  bool pilotLengths = true;  // length_selection: pilot
  int chains = 64;
  static MltSettings read(Params& p);
};

class Mlt final : public Integrator {
 public:
  std::string splitRefusal() const override {
    return "its passes are Markov chains' mutations; each chunk would restart the chains and re-estimate b";
  }
  explicit Mlt(MltSettings s);
  ~Mlt() override;
  void preprocess(const Scene& scene, const Sampler& prototype) override;
  void renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass, PassStats& stats) override;
  std::vector<std::string> summaryLines() const override;
  bool independentPasses() const override { return false; }

  const mlt::Bootstrap& bootstrap() const { return bootstrap_; }
  mlt::ChainStats chainStats() const;

 private:
  MltSettings settings_;
  std::unique_ptr<PathEstimator> estimator_;  // base: path
  std::unique_ptr<mlt::PrimarySpaceIntegrand> integrand_;
  mlt::Bootstrap bootstrap_;
  std::vector<mlt::MarkovChain> chains_;
  uint64_t unreportedRays_ = 0;  // the bootstrap's, added to the first pass's count
};

}  // namespace lb
