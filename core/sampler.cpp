#include "core/sampler.h"
#include "core/samplers/halton.h"
#include "core/samplers/sobol.h"

namespace lb {

uint32_t permuteIndex(uint32_t i, uint32_t n, uint32_t key) {
  uint32_t w = n - 1;
  w |= w >> 1, w |= w >> 2, w |= w >> 4, w |= w >> 8, w |= w >> 16;
  do {
    i ^= key;
    i *= 0xe170893d;
    i ^= key >> 16;
    i ^= (i & w) >> 4;
    i ^= key >> 8;
    i *= 0x0929eb3f;
    i ^= key >> 23;
    i ^= (i & w) >> 1;
    i *= 1 | key >> 27;
    i *= 0x6935fa69;
    i ^= (i & w) >> 11;
    i *= 0x74dcb303;
    i ^= (i & w) >> 2;
    i *= 0x9e501cc3;
    i ^= (i & w) >> 2;
    i *= 0xc860a3df;
    i &= w;
    i ^= i >> 5;
  } while (i >= n);
  // Kensler's final shift: without it the image of a fixed i is not uniform
  // over keys unless n is a power of two (strata 3 gave stratum 0 with
  // frequencies 0.375/0.25/0.375 for the first digit), so a budget that stops
  // mid-block was biased.
  return (i + key) % n;
}

void StratifiedSampler::start(uint64_t pixel, uint64_t sample) {
  uint64_t blockSize = uint64_t(n_) * n_;
  pixel_ = pixel;
  sample_ = sample;
  block_ = sample / blockSize;
  indexInBlock_ = uint32_t(sample % blockSize);
  dimension_ = 0;
}

// A request at dimension d takes stratum permute(index in block) and a jitter
// inside it, both hashed from d, so the values do not depend on the order of
// requests before it.
float StratifiedSampler::get1D() {
  uint32_t count = uint32_t(n_ * n_), d = dimension_++;
  uint32_t s = permuteIndex(indexInBlock_, count, uint32_t(hashValues(seed_, pixel_, block_, d)));
  Pcg32 jitter(hashValues(seed_, pixel_, sample_, d), mixBits(seed_ + 1));
  return std::min(OneMinusEpsilon, (s + jitter.next1D()) / count);
}

Vec2 StratifiedSampler::get2D() {
  uint32_t d = dimension_;
  dimension_ += 2;
  uint32_t s = permuteIndex(indexInBlock_, uint32_t(n_ * n_), uint32_t(hashValues(seed_, pixel_, block_, d)));
  Pcg32 jitter(hashValues(seed_, pixel_, sample_, d), mixBits(seed_ + 1));
  Vec2 j = jitter.next2D();
  return {std::min(OneMinusEpsilon, (s % n_ + j.x) / n_), std::min(OneMinusEpsilon, (s / n_ + j.y) / n_)};
}

std::unique_ptr<Sampler> makeSampler(const SamplerSettings& s, uint64_t seed, int width, int height) {
  if (s.type == "stratified") return std::make_unique<StratifiedSampler>(seed, s.strata);
  if (s.type == "sobol") return std::make_unique<SobolSampler>(seed);
  if (s.type == "zsobol") return std::make_unique<ZSobolSampler>(seed, s.spp, width, height);
  if (s.type == "halton") return std::make_unique<HaltonSampler>(seed);
  return std::make_unique<IndependentSampler>(seed);
}

}  // namespace lb
