#pragma once
// Bidirectional path tracing (Veach 1997 ch. 10; Veach & Guibas 1995). Each
// sample builds a camera subpath z0…z(t-1) and a light subpath y0…y(s-1), both
// with Russian roulette, and evaluates every connection strategy (s, t),
// weighted by multiple importance sampling over all strategies that could have
// produced the same path, computed in time linear in its length by the
// pdf-ratio recursion (pbrt-v3 §16.3.4, MISWeight). The vertices, subpaths,
// connections and weights are shared with the other bidirectional estimators
// and live in integrators/bidirectional/; this is the integrator around them.
//
//   max_depth, rr, rr_depth  path length in segments and roulette on both
//                            subpaths (path_length.h), as in `path` and `light`
//   mis              power   power (β = 2) | balance | uniform (1 / number of strategies)
//   strategy_images  0       write weighted and unweighted images of every (s, t)
//                            with s + t - 1 <= this length (0: none)
//   mis: variance_aware      the balance heuristic over c_{s,t} p_{s,t}, c learned per
//                            pixel block in the first pilot_passes (1) passes over
//                            factor_block² (8²) pixels (Grittmann et al. 2019;
//                            bidirectional/strategy_factors.h)
//   regularize       false   path-space regularization (core/bsdfs/regularization.h):
//                            delta vertices with a non-delta one between them and the
//                            camera scatter by rough twins, regularize_roughness α_0
//                            (0.1) shrinking as (k + 1)^-regularize_exponent (1/6)
#include <memory>
#include <vector>
#include "core/bsdfs/regularization.h"
#include "core/params.h"
#include "integrators/path_length.h"
#include "integrators/bidirectional/connect.h"
#include "integrators/bidirectional/strategy_factors.h"
#include "integrators/integrator.h"

namespace lb {

struct BdptSettings {
  PathLength length;
  bidir::MisWeighting mis = bidir::MisWeighting::Power;
  bool varianceAware = false;  // mis: variance_aware (then mis is Balance)
  int pilotPasses = 1, factorBlock = 8;
  int strategyImages = 0;
  RegularizationSettings regularization;
  static BdptSettings read(Params& p);
};


class Bdpt final : public Integrator {
 public:
  // Unbiased with independent passes: chunks of passes split a render exactly
  // (not a regularized one, whose roughness depends on the pass).
  std::string splitRefusal() const override {
    if (settings_.varianceAware) return "its factors are learned from the render's first passes";
    return settings_.regularization.enabled ? "regularize: its roughness follows the passes' count" : "";
  }
  explicit Bdpt(BdptSettings s);
  void preprocess(const Scene& scene, const Sampler& prototype) override;
  void renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass, PassStats& stats) override;
  std::vector<ExrLayer> extraLayers() const override;
  // Per-strategy film (after a render with strategy_images > 0), or null.
  // mis: variance_aware: the factors (created by the first pass, or given
  // here, finished or not, by a test that wants to control them).
  const bidir::StrategyFactors* strategyFactors() const { return factors_.get(); }
  void setStrategyFactors(std::unique_ptr<bidir::StrategyFactors> f) { factors_ = std::move(f); }
  const Film* strategyFilm(int s, int t, bool weighted) const {
    int k = strategyIndex(s, t);
    return k < 0 ? nullptr : (weighted ? weighted_ : unweighted_)[size_t(k)].get();
  }

 private:
  BdptSettings settings_;
  // Per-strategy films (weighted, unweighted), index strategyIndex(s, t).
  std::vector<std::unique_ptr<Film>> weighted_, unweighted_;
  std::vector<std::pair<int, int>> strategies_;
  // regularize: the scene's rough twins for the pass being rendered.
  std::unique_ptr<Regularization> regularization_;
  std::unique_ptr<bidir::StrategyFactors> factors_;
  int pilotPassesDone_ = 0;
  // A t = 1 strategy's unweighted splat, kept per tile during a pilot pass.
  struct LightTracingRecord {
    Vec2 raster;
    int s;
    double value;
  };
  // After a pilot pass: each pixel's sum of its t = 1 splats per s, recorded
  // in tile order, then finish() after the last pilot pass.
  void learnFromLightTracing(const std::vector<std::vector<LightTracingRecord>>& records);
  int strategyIndex(int s, int t) const;
};

}  // namespace lb
