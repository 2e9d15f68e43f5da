#pragma once
// PCG32 (O'Neill 2014): small, fast, and seekable by stream. Every sample is
// seeded from (seed, pixel, sample index) through a hash, never from a thread id,
// so an image is bit-identical whatever the thread count.
#include <cstdint>
#include "core/math.h"

namespace lb {

// 64-bit finaliser of MurmurHash3 / splitmix64; mixes the seed tuple.
inline uint64_t mixBits(uint64_t v) {
  v ^= v >> 31;
  v *= 0x7fb5d329728ea185ULL;
  v ^= v >> 27;
  v *= 0x81dadef4bc2dd44dULL;
  v ^= v >> 33;
  return v;
}
inline uint64_t hashCombine(uint64_t a, uint64_t b) { return mixBits(a ^ (mixBits(b) + 0x9e3779b97f4a7c15ULL + (a << 6) + (a >> 2))); }
template <typename... Ts>
uint64_t hashValues(uint64_t first, Ts... rest) {
  uint64_t h = mixBits(first);
  ((h = hashCombine(h, uint64_t(rest))), ...);
  return h;
}

class Pcg32 {
 public:
  Pcg32() { seed(0x853c49e6748fea9bULL, 0xda3e39cb94b95bdbULL); }
  Pcg32(uint64_t state, uint64_t stream) { seed(state, stream); }

  void seed(uint64_t initState, uint64_t stream) {
    state_ = 0;
    inc_ = (stream << 1u) | 1u;
    nextU32();
    state_ += initState;
    nextU32();
  }
  uint32_t nextU32() {
    uint64_t old = state_;
    state_ = old * 0x5851f42d4c957f2dULL + inc_;
    uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
  }
  // Uniform in [0, 1): 24 random mantissa bits, never rounds up to 1.
  float next1D() { return std::min(OneMinusEpsilon, float(nextU32() >> 8) * 0x1p-24f); }
  Vec2 next2D() {
    float a = next1D();
    return {a, next1D()};
  }
  uint32_t uniformInt(uint32_t bound) { return uint32_t((uint64_t(nextU32()) * bound) >> 32); }
  // Skips `delta` draws in O(log delta) (Brown 1994, "Random number generation
  // with arbitrary strides", as in O'Neill's pcg32_advance).
  void advance(uint64_t delta) {
    uint64_t curMult = 0x5851f42d4c957f2dULL, curPlus = inc_, accMult = 1, accPlus = 0;
    for (; delta > 0; delta >>= 1) {
      if (delta & 1) {
        accMult *= curMult;
        accPlus = accPlus * curMult + curPlus;
      }
      curPlus = (curMult + 1) * curPlus;
      curMult *= curMult;
    }
    state_ = accMult * state_ + accPlus;
  }

 private:
  uint64_t state_, inc_;
};

}  // namespace lb
