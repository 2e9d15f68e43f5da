#pragma once
// Per-sample random number streams. A sampler is started for (pixel, sample
// index) and hands out dimensions: get1D() uses one, get2D() two. Every value
// is a function of (seed, pixel, sample index, dimension) only, so images do
// not depend on thread scheduling, and setDimension() lets an integrator give
// each path vertex a fixed range of dimensions (integrators/path_estimator/path_estimator.h
// documents its layout) so a low-discrepancy sampler's strata line up from one
// path to the next.
//
// Draw each value in its own statement: f(get1D(), get2D()) takes its
// arguments in an order C++ leaves unspecified, so which dimensions the lobe
// and the direction get would depend on the compiler (and the image with
// them). A BSDF sample takes the direction's two dimensions first, then the
// lobe's one (the order g++ gave the calls written as one expression):
//   Vec2 uDir = sampler.get2D();
//   float uLobe = sampler.get1D();
//   auto bs = bsdf.sample(wo, uLobe, uDir, mode);
//
// The samplers (sampler: {type: ...} in a scene, a configuration, or --sampler):
//   independent  PCG32 per sample                           (core/sampler.h)
//   stratified   jittered strata in blocks of strata² samples (core/sampler.h)
//   sobol        Owen-scrambled Sobol', padded per 1-D/2-D request (core/samplers/sobol.h)
//   zsobol       the same points in Morton order over the image (core/samplers/sobol.h)
//   halton       Halton with random digit permutations     (core/samplers/halton.h)
#include <memory>
#include <string>
#include "core/rng.h"

namespace lb {

// The most samples per pixel any budget may ask for (render --spp and
// --chunk-spp, an experiment's and a reference's spp, Mitsuba's
// sample_count): 2^31 - 1, what a YAML budget (an int) holds. Checked before
// anything renders; `--spp 18446744073709551615` ran for ever (issue 34).
inline constexpr uint64_t kMaxSpp = 2147483647;

class Sampler {
 public:
  virtual ~Sampler() = default;
  // Starts (pixel, sample index) at dimension 0.
  virtual void start(uint64_t pixelIndex, uint64_t sampleIndex) = 0;
  virtual float get1D() = 0;
  virtual Vec2 get2D() = 0;
  // The dimension the next get1D()/get2D() uses, and a jump to another one.
  uint32_t dimension() const { return dimension_; }
  virtual void setDimension(uint32_t d) { dimension_ = d; }
  virtual std::unique_ptr<Sampler> clone() const = 0;
  // The run's seed: integrators derive other random streams (photons) from it.
  virtual uint64_t seed() const = 0;

 protected:
  uint32_t dimension_ = 0;
};

// One PCG32 stream per (pixel, sample); dimension d is the stream's d-th
// draw. Jumps forward are a few draws (the path tracer's slots skip a handful
// of dimensions per vertex), longer or backward jumps re-seed and advance.
class IndependentSampler final : public Sampler {
 public:
  explicit IndependentSampler(uint64_t seed) : seed_(seed) {}
  void start(uint64_t pixel, uint64_t sample) override {
    key_ = hashValues(seed_, pixel, sample);
    rng_.seed(key_, mixBits(seed_));
    dimension_ = 0;
  }
  float get1D() override {
    ++dimension_;
    return rng_.next1D();
  }
  Vec2 get2D() override {
    dimension_ += 2;
    return rng_.next2D();
  }
  void setDimension(uint32_t d) override {
    if (d >= dimension_ && d - dimension_ <= 8) {
      for (; dimension_ < d; ++dimension_) rng_.nextU32();
      return;
    }
    rng_.seed(key_, mixBits(seed_));
    rng_.advance(d);
    dimension_ = d;
  }
  std::unique_ptr<Sampler> clone() const override { return std::make_unique<IndependentSampler>(*this); }
  uint64_t seed() const override { return seed_; }

 private:
  uint64_t seed_, key_ = 0;
  Pcg32 rng_;
};

// Jittered stratification in blocks: sample indices are grouped in blocks of
// n² samples; within a block each 2-D request visits every one of the n×n
// strata once, in an order randomly permuted per (pixel, block, dimension), and
// 1-D requests visit n² strata likewise. Each sample is marginally uniform, so
// a budget that stops mid-block stays unbiased; full blocks are stratified.
class StratifiedSampler final : public Sampler {
 public:
  StratifiedSampler(uint64_t seed, int strataPerAxis) : seed_(seed), n_(strataPerAxis) {}
  void start(uint64_t pixel, uint64_t sample) override;
  float get1D() override;
  Vec2 get2D() override;
  std::unique_ptr<Sampler> clone() const override { return std::make_unique<StratifiedSampler>(*this); }
  uint64_t seed() const override { return seed_; }

 private:
  uint64_t seed_, pixel_ = 0, sample_ = 0, block_ = 0;
  uint32_t indexInBlock_ = 0;
  int n_;
};

struct SamplerSettings {
  std::string type = "independent";  // independent | stratified | sobol | zsobol | halton
  int strata = 4;                    // stratified: strata per axis (blocks of strata² samples)
  int spp = 64;                      // zsobol: samples per pixel of one Morton-ordered pattern (a power of 2)
};
const char* const SamplerTypes[] = {"independent", "stratified", "sobol", "zsobol", "halton"};

// `width` × `height` is the image the pixel indices y·width + x refer to
// (zsobol orders pixels along a Morton curve over it).
std::unique_ptr<Sampler> makeSampler(const SamplerSettings& s, uint64_t seed, int width = 1, int height = 1);

// Kensler 2013, "Correlated Multi-Jittered Sampling": a hash-based random
// permutation of [0, n) evaluated at index i without storing the permutation.
uint32_t permuteIndex(uint32_t i, uint32_t n, uint32_t key);

}  // namespace lb
