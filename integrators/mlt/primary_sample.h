#pragma once
// Primary sample space (Kelemen, Szirmay-Kalos, Antal, Csonka 2002): a path is
// a function of the uniform numbers its sampler hands out, so a Markov chain
// can walk the unit hypercube of those numbers instead of path space. This
// file holds the chain's state, a vector of coordinates in [0, 1), and its
// two mutations (Kelemen et al. §3.2):
//  * large step: every coordinate drawn afresh, uniformly (independent of
//    the current state, so T(x→y) = 1);
//  * small step: every coordinate moved by Kelemen's exponential perturbation
//    (perturb() below), wrapped around the unit interval.
// Both kernels are symmetric, T(x→y) = T(y→x), so the Metropolis-Hastings
// acceptance reduces to min(1, f(y)/f(x)) (metropolis.h).
//
// Coordinates are mutated lazily, when a path reads them (as in pbrt-v3/v4's
// MLTSampler): a coordinate last touched at accepted iteration m and read at
// iteration i receives the i − m small steps it missed (or a fresh value if a
// large step was accepted since), which is the same chain as mutating every
// coordinate at every step. Unlike pbrt-v4, a coordinate first read after the
// chain has started is drawn uniformly (the chain's initial state is uniform
// in every coordinate), not perturbed from 0.
//
// A path's numbers come from several streams (camera subpath, light subpath,
// connections, strategy choice), interleaved in one vector, so that a change
// in how many numbers one subpath uses does not shift the meaning of the
// others' (Hachisuka et al. 2014 §4; pbrt-v3 §16.4.4).
#include <memory>
#include <vector>
#include "core/rng.h"
#include "core/sampler.h"

namespace lb::mlt {

// Kelemen's perturbation: an offset of size s1 ≤ |Δ| ≤ s2 with density
// 1/(|Δ| ln(s2/s1)) (log-uniform), either sign with probability ½, wrapped
// into [0, 1). Kelemen et al. used s1 = 1/1024, s2 = 1/64; `sigma` (the key)
// is s2, and s1 = s2/16 keeps their ratio.
struct SmallStep {
  float s1 = 1.f / 1024, s2 = 1.f / 64;
  static SmallStep fromSigma(float sigma) { return {sigma / 16, sigma}; }
  // σ₁, the standard deviation of one offset (0.0066 for Kelemen's sizes).
  float stepDeviation() const;
};
float perturb(float x, float u, const SmallStep& step);
// n successive perturbations, from the uniforms of `rng`: exactly for
// n ≤ ExactSteps, else their sum by its normal limit (primary_sample.cpp).
float perturbRepeatedly(float x, uint64_t n, const SmallStep& step, Pcg32& rng);
constexpr uint64_t ExactSteps = 32;

class PrimarySampleVector {
 public:
  PrimarySampleVector(int streams, SmallStep step, uint64_t seed, uint64_t stream);
  // A new proposal: `large` decides the kernel. Coordinates then change as
  // they are read.
  void startIteration(bool large);
  void accept();
  void reject();  // every coordinate read this iteration returns to its old value
  // Draws for the mutations come from a new stream from now on (a chain
  // started from a bootstrap sample must not repeat that sample's draws).
  void reseed(uint64_t seed, uint64_t stream) { rng_.seed(seed, stream); }

  // Coordinate `index` of stream `stream`, mutated up to this iteration.
  float get(int stream, uint32_t index);
  int streams() const { return streams_; }
  bool largeStep() const { return largeStep_; }
  uint64_t iteration() const { return uint64_t(iteration_); }

 private:
  struct Coordinate {
    float value = 0, backup = 0;
    int64_t modified = -1, backupModified = -1;  // -1: never drawn
  };
  int streams_;
  SmallStep step_;
  Pcg32 rng_;
  std::vector<Coordinate> x_;
  // The initial state (iteration 0) counts as an accepted large step.
  int64_t iteration_ = 0, lastLargeStep_ = 0;
  bool largeStep_ = true;
};

// A view of one stream as a Sampler, for code written against samplers (the
// path estimator, the bidirectional subpaths). start() returns to the
// stream's first coordinate; dimensions index the stream.
class PrimarySampleStream final : public Sampler {
 public:
  PrimarySampleStream(PrimarySampleVector& vector, int stream) : vector_(&vector), stream_(stream) {}
  void start(uint64_t, uint64_t) override { dimension_ = 0; }
  float get1D() override { return vector_->get(stream_, dimension_++); }
  Vec2 get2D() override {
    float a = get1D();
    return {a, get1D()};
  }
  std::unique_ptr<Sampler> clone() const override { return std::make_unique<PrimarySampleStream>(*this); }
  uint64_t seed() const override { return 0; }

 private:
  PrimarySampleVector* vector_;
  int stream_;
};

}  // namespace lb::mlt
