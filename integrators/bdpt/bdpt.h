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
#include "integrators/integrator.h"

namespace lb {

struct BdptSettings {
  PathLength length;
  bidir::MisWeighting mis = bidir::MisWeighting::Power;
  int strategyImages = 0;
  RegularizationSettings regularization;
  static BdptSettings read(Params& p);
};


class Bdpt final : public Integrator {
 public:
  // Unbiased with independent passes: chunks of passes split a render exactly
  // (not a regularized one, whose roughness depends on the pass).
  std::string splitRefusal() const override {
    return settings_.regularization.enabled ? "regularize: its roughness follows the passes' count" : "";
  }
  explicit Bdpt(BdptSettings s);
  void renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass, PassStats& stats) override;
  std::vector<ExrLayer> extraLayers() const override;
  // Per-strategy film (after a render with strategy_images > 0), or null.
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
  int strategyIndex(int s, int t) const;
};

}  // namespace lb
