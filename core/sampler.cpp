#include "core/sampler.h"

namespace lb {

namespace {
// Kensler 2013, "Correlated Multi-Jittered Sampling": a hash-based random
// permutation of [0, n) evaluated at index i without storing the permutation.
uint32_t permute(uint32_t i, uint32_t n, uint32_t key) {
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
  return i;
}
}  // namespace

void StratifiedSampler::start(uint64_t pixel, uint64_t sample) {
  uint64_t blockSize = uint64_t(n_) * n_;
  pixel_ = pixel;
  block_ = sample / blockSize;
  indexInBlock_ = uint32_t(sample % blockSize);
  dimension_ = 0;
  rng_.seed(hashValues(seed_, pixel, sample), mixBits(seed_ + 1));
}

uint32_t StratifiedSampler::stratum(uint32_t count) {
  uint32_t key = uint32_t(hashValues(seed_, pixel_, block_, dimension_++));
  return permute(indexInBlock_, count, key);
}

float StratifiedSampler::get1D() {
  uint32_t count = uint32_t(n_ * n_);
  uint32_t s = stratum(count);
  return std::min(OneMinusEpsilon, (s + rng_.next1D()) / count);
}

Vec2 StratifiedSampler::get2D() {
  uint32_t s = stratum(uint32_t(n_ * n_));
  Vec2 j = rng_.next2D();
  return {std::min(OneMinusEpsilon, (s % n_ + j.x) / n_), std::min(OneMinusEpsilon, (s / n_ + j.y) / n_)};
}

}  // namespace lb
