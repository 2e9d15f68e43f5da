#pragma once
// Halton points with random digit permutations.
//
// Dimension d of sample i is the radical inverse of i in the d-th prime base
// b (Halton 1960): with i = Σ_j a_j b^(j−1), x = Σ_j a_j b^−j. Plain Halton
// points are badly correlated in large bases; permuting the digits fixes that
// (Braaten & Weller 1979, "An improved low-discrepancy sequence for
// multidimensional quasi-Monte Carlo integration"), and drawing the
// permutations at random (one per digit position, independent of the digit
// values above it: pbrt-v4 §8.6.2, "Random digit permutations") makes the
// points a randomized QMC set, each point alone uniform.
//
// Here every (seed, pixel, dimension, digit position j) gets its own
// permutation: permuteIndex(·, b, key) (Kensler 2013) then a random cyclic
// shift (halton.cpp says why), so every pixel is an independent
// randomization. Digits are evaluated, zeros beyond i's last digit
// included (permuted zeros are not zero, so the points are not confined to a
// lattice), until b^−j falls below 2^−24, float resolution; the sum is done in
// double and rounded down to a float below 1. The first b^k samples (indeed
// any b^k consecutive ones starting at a multiple of b^k) fall one in each
// interval [a/b^k, (a+1)/b^k). The sample index is used as given (64 bits);
// digits of it beyond float resolution do not change the value, so in base b
// points repeat after b^J samples (2^25 in base 2), far beyond any budget.
//
// Dimensions ≥ MaxDimensions (the first 1024 primes) fall back to uniform
// random values hashed from (seed, pixel, sample, dimension): unbiased, not
// stratified.
#include "core/sampler.h"

namespace lb {

class HaltonSampler final : public Sampler {
 public:
  static constexpr uint32_t MaxDimensions = 1024;

  explicit HaltonSampler(uint64_t seed) : seed_(seed) {}
  void start(uint64_t pixel, uint64_t sample) override {
    pixel_ = pixel, sample_ = sample;
    dimension_ = 0;
  }
  float get1D() override { return value(dimension_++); }
  Vec2 get2D() override {
    Vec2 u(value(dimension_), value(dimension_ + 1));
    dimension_ += 2;
    return u;
  }
  std::unique_ptr<Sampler> clone() const override { return std::make_unique<HaltonSampler>(*this); }
  uint64_t seed() const override { return seed_; }

  // The base of dimension d < MaxDimensions: the d-th prime (2, 3, 5, ...).
  static uint32_t primeBase(uint32_t d);

 private:
  // Dimension d of the current (pixel, sample).
  float value(uint32_t d) const;

  uint64_t seed_, pixel_ = 0, sample_ = 0;
};

}  // namespace lb
