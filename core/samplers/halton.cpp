#include "core/samplers/halton.h"
#include <vector>

namespace lb {

namespace {

// The first HaltonSampler::MaxDimensions primes by the sieve of Eratosthenes,
// computed once (the 1024th prime is 8161). Thread-safe: a function-local
// static is initialised once (C++11 §6.7).
const std::vector<uint32_t>& primes() {
  static const std::vector<uint32_t> table = [] {
    std::vector<uint32_t> p;
    for (uint32_t limit = 8192; p.size() < HaltonSampler::MaxDimensions; limit *= 2) {
      std::vector<bool> composite(limit, false);
      p.clear();
      for (uint32_t n = 2; n < limit && p.size() < HaltonSampler::MaxDimensions; ++n) {
        if (composite[n]) continue;
        p.push_back(n);
        for (uint64_t m = uint64_t(n) * n; m < limit; m += n) composite[m] = true;
      }
    }
    return p;
  }();
  return table;
}

// A double in [0, 1) to the largest float not above it (rounding to nearest
// could carry a point across the upper edge of its interval, or up to 1).
float roundDown(double v) {
  float f = float(v);
  if (double(f) > v) f = std::nextafter(f, 0.f);
  return std::min(OneMinusEpsilon, f);
}

}  // namespace

uint32_t HaltonSampler::primeBase(uint32_t d) { return primes()[d]; }

// x = Σ_j π_j(a_j) b^−j: π_j a random permutation of the b digits for digit
// position j, keyed by (seed, pixel, d, j). π_j is permuteIndex followed by a
// random cyclic shift of the digit drawn from the key's other half. Kensler's
// hash alone is not uniform over keys when b is not a power of two (in base 3,
// digit 0 went to 0, 1, 2 with frequencies 0.375, 0.25, 0.375), which would
// bias every sample; permuteIndex ends with Kensler's own shift (i + key) mod
// b, and the shift here, independent of the permutation's key, makes π_j(a)
// uniform for every a whatever the hash does.
float HaltonSampler::value(uint32_t d) const {
  if (d >= MaxDimensions) return float(uint32_t(hashValues(seed_, pixel_, sample_, d)) >> 8) * 0x1p-24f;
  uint32_t base = primes()[d];
  uint64_t dimensionKey = hashValues(seed_, pixel_, d), i = sample_;
  double invBase = 1.0 / base, weight = 1.0, x = 0;
  for (uint32_t j = 1;; ++j) {
    weight *= invBase;
    uint32_t digit = uint32_t(i % base);
    i /= base;
    uint64_t key = hashCombine(dimensionKey, j);
    uint32_t shift = uint32_t(((key >> 32) * base) >> 32);  // uniform in [0, base)
    uint32_t permuted = permuteIndex(digit, base, uint32_t(key)) + shift;
    x += (permuted >= base ? permuted - base : permuted) * weight;
    if (weight < 0x1p-24) break;  // the rest is below float resolution
  }
  return roundDown(x);
}

}  // namespace lb
