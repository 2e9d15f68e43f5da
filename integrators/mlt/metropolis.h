#pragma once
// The Metropolis sampler of primary sample space MLT, independent of what is
// integrated (Kelemen et al. 2002; Veach 1997 ch. 11):
//
//  * An integrand maps a primary sample vector u to contributions (pixel
//    position, colour); its scalar target f(u) is their summed luminance.
//    Normalised so that pixel j's value is  I_j = P ∫ h_j(u) du,  with P the
//    number of pixels and h_j the contributions landing in pixel j.
//  * Bootstrap: b = ∫ f(u) du is estimated from n independent uniform
//    vectors, b̂ = (1/n) Σ f(u_i), with relative standard error
//    s_f / (b̂ √n); the chains start at bootstrap samples drawn in proportion
//    to f(u_i) (sampling-importance-resampling, so a chain starts
//    approximately in its stationary distribution f/b — "start-up bias" is
//    what remains of the approximation, and it fades as the chain runs).
//  * Each mutation proposes y from x (primary_sample.h), accepts with
//    a = min(1, f(y)/f(x)) (both kernels are symmetric), and records both
//    states with their expected weights (Veach 1997 §11.3.4, Kelemen et al.
//    §5): y's contributions × a, x's × (1 − a), each divided by its own f.
//    After N mutations in all,  Î_j = P · b̂/N · Σ (weight · h_j / f).
//  * A state's weight accumulates while the chain stays in it and is splatted
//    once when the chain leaves it (or a pass ends): the same sums, fewer
//    splats.
#include <cstdint>
#include <functional>
#include <vector>
#include "core/film.h"
#include "integrators/mlt/primary_sample.h"

namespace lb::mlt {

struct Contribution {
  Vec2 raster;
  Color value;
};

class PrimarySpaceIntegrand {
 public:
  virtual ~PrimarySpaceIntegrand() = default;
  virtual int streams() const = 0;
  // Appends u's contributions to `out` (cleared by the caller); rays traced
  // are added to `rays`. Must be a pure function of u's coordinates.
  virtual void evaluate(PrimarySampleVector& u, std::vector<Contribution>& out, uint64_t& rays) const = 0;
};

// f(u): the summed luminance of the contributions. A proposal with a
// non-finite contribution is given f = 0 by the chain (and counted), so it
// is never accepted: a chain only leaves states with f > 0 for states with
// f > 0 (it starts at one, chosen in proportion to f).
float targetValue(const std::vector<Contribution>& c);

// Metropolis-Hastings acceptance for a symmetric kernel: min(1, f(y)/f(x)),
// and 1 from a state with f(x) = 0 (the chain leaves such states at once).
float acceptance(float fCurrent, float fProposed);

struct MetropolisSettings {
  float largeStepProbability = 0.3f;
  SmallStep smallStep;
};

// The vector bootstrap sample `index` starts from, before any mutation.
PrimarySampleVector bootstrapVector(int streams, const SmallStep& step, uint64_t seed, uint64_t index);

// Evaluates bootstrap samples 0 … n−1 in parallel, sample i at
// bootstrapVector(…, seed, i), and hands each to `record(i, u, c)` (from
// any thread; i is distinct per call, so writing slot i of an array is
// safe). Each result depends on i alone, never on the threads. `onProgress(k)`
// after each block of k samples. Shared by the bootstrap of b and mmlt's
// per-length estimates.
void forEachBootstrapSample(
    const PrimarySpaceIntegrand& integrand, const SmallStep& step, uint64_t seed, uint64_t n, uint64_t& rays,
    const std::function<void(uint64_t i, PrimarySampleVector& u, const std::vector<Contribution>& c)>& record,
    const std::function<void(uint64_t)>& onProgress = {});

struct Bootstrap {
  double b = 0;                      // the estimate of ∫ f du
  double relativeStandardError = 0;  // s_f / (b √n); NaN if b = 0
  uint64_t samples = 0, nonZero = 0, nonFinite = 0;
  std::vector<double> cdf;  // running sums of f(u_i), for choosing chain starts
  // The bootstrap sample chosen with probability f(u_i)/Σ f by `u` ∈ [0, 1).
  uint64_t choose(float u) const;
};
// n bootstrap samples, in parallel; the result does not depend on the
// thread count. `onProgress(k)` is called after each block of k samples.
Bootstrap runBootstrap(const PrimarySpaceIntegrand& integrand, const MetropolisSettings& settings, uint64_t seed,
                       uint64_t n, uint64_t& rays, const std::function<void(uint64_t)>& onProgress = {});

struct ChainStats {
  uint64_t smallProposed = 0, smallAccepted = 0, largeProposed = 0, largeAccepted = 0, nonFinite = 0;
  ChainStats& operator+=(const ChainStats& o);
};

class MarkovChain {
 public:
  // Starts at bootstrap sample `start` (re-evaluated: the integrand is a pure
  // function of u), then mutates with draws of its own stream `chain`.
  MarkovChain(const PrimarySpaceIntegrand& integrand, const MetropolisSettings& settings, uint64_t seed,
              uint64_t start, uint64_t chain, uint64_t& rays);
  // `mutations` steps; splats each state left (and the current one at the
  // end) with weight · scale / f. `scale` = P · b̂ / (mutations of all chains
  // in this pass). Non-finite contributions of a proposal are appended to
  // `nonFinite` (their raster) and the proposal is rejected.
  void run(uint64_t mutations, double scale, std::vector<Splat>& splats, std::vector<Vec2>& nonFinite,
           uint64_t& rays);
  const ChainStats& stats() const { return stats_; }
  float currentValue() const { return fCurrent_; }

 private:
  void splatCurrent(double scale, std::vector<Splat>& splats);

  const PrimarySpaceIntegrand& integrand_;
  MetropolisSettings settings_;
  PrimarySampleVector u_;
  Pcg32 decisions_;  // step kinds and acceptances
  std::vector<Contribution> current_, proposed_;
  float fCurrent_ = 0;
  double weight_ = 0;  // the current state's accumulated expected weight, not yet splatted
  ChainStats stats_;
};

}  // namespace lb::mlt
