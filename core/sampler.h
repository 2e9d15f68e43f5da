#pragma once
// Per-sample random number streams. A sampler is started for (pixel, sample
// index) and hands out dimensions in order; its state depends only on the seed,
// the pixel and the sample index, so images do not depend on thread scheduling.
#include <memory>
#include <string>
#include "core/rng.h"

namespace lb {

class Sampler {
 public:
  virtual ~Sampler() = default;
  virtual void start(uint64_t pixelIndex, uint64_t sampleIndex) = 0;
  virtual float get1D() = 0;
  virtual Vec2 get2D() = 0;
  virtual std::unique_ptr<Sampler> clone() const = 0;
  // The run's seed: integrators derive other random streams (photons) from it.
  virtual uint64_t seed() const = 0;
};

class IndependentSampler final : public Sampler {
 public:
  explicit IndependentSampler(uint64_t seed) : seed_(seed) {}
  void start(uint64_t pixel, uint64_t sample) override { rng_.seed(hashValues(seed_, pixel, sample), mixBits(seed_)); }
  float get1D() override { return rng_.next1D(); }
  Vec2 get2D() override { return rng_.next2D(); }
  std::unique_ptr<Sampler> clone() const override { return std::make_unique<IndependentSampler>(*this); }
  uint64_t seed() const override { return seed_; }

 private:
  uint64_t seed_;
  Pcg32 rng_;
};

// Jittered stratification in blocks: sample indices are grouped in blocks of
// n² samples; within a block each 2-D dimension visits every one of the n×n
// strata once, in an order randomly permuted per (pixel, block, dimension), and
// 1-D dimensions visit n² strata likewise. Each sample is marginally uniform, so
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
  uint32_t stratum(uint32_t count);
  uint64_t seed_, pixel_ = 0, block_ = 0;
  uint32_t indexInBlock_ = 0, dimension_ = 0;
  int n_;
  Pcg32 rng_;
};

struct SamplerSettings {
  std::string type = "independent";  // independent | stratified
  int strata = 4;                    // stratified: strata per axis (blocks of strata² samples)
};

inline std::unique_ptr<Sampler> makeSampler(const SamplerSettings& s, uint64_t seed) {
  if (s.type == "stratified") return std::make_unique<StratifiedSampler>(seed, s.strata);
  return std::make_unique<IndependentSampler>(seed);
}

}  // namespace lb
