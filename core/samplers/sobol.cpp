#include "core/samplers/sobol.h"

namespace lb {

// Swap adjacent bits, then pairs, nibbles, bytes and halves (Warren, Hacker's
// Delight, §7-1).
uint32_t reverseBits32(uint32_t v) {
  v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
  v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
  v = ((v >> 4) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4);
  v = ((v >> 8) & 0x00ff00ffu) | ((v & 0x00ff00ffu) << 8);
  return (v >> 16) | (v << 16);
}

uint32_t sobolDimension0(uint32_t i) { return reverseBits32(i); }

// x = C·i over GF(2): xor the columns v_k of the set bits k of i.
uint32_t sobolDimension1(uint32_t i) {
  uint32_t r = 0;
  for (uint32_t v = 1u << 31; i != 0; i >>= 1, v ^= v >> 1)
    if (i & 1) r ^= v;
  return r;
}

// Adding the seed and xoring x with x times an even constant change each bit
// only as a function of the bits below it, and both are invertible.
uint32_t laineKarrasPermutation(uint32_t x, uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

uint32_t nestedUniformScramble(uint32_t x, uint32_t seed) {
  return reverseBits32(laineKarrasPermutation(reverseBits32(x), seed));
}

namespace {

// (seed, pixel, dimension), and the high half of the sample index if it has one.
uint64_t requestKey(uint64_t seed, uint64_t pixel, uint64_t sample, uint32_t dim) {
  uint64_t key = hashValues(seed, pixel, dim);
  return (sample >> 32) != 0 ? hashValues(key, sample >> 32) : key;
}

// Morton code: the bits of v spread to the even positions of a 64-bit word.
uint64_t spreadBits(uint32_t v) {
  uint64_t x = v;
  x = (x | (x << 16)) & 0x0000ffff0000ffffULL;
  x = (x | (x << 8)) & 0x00ff00ff00ff00ffULL;
  x = (x | (x << 4)) & 0x0f0f0f0f0f0f0f0fULL;
  x = (x | (x << 2)) & 0x3333333333333333ULL;
  x = (x | (x << 1)) & 0x5555555555555555ULL;
  return x;
}

// The 24 permutations of {0,1,2,3} in lexicographic order.
constexpr uint8_t DigitPermutations[24][4] = {
    {0, 1, 2, 3}, {0, 1, 3, 2}, {0, 2, 1, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {0, 3, 2, 1},
    {1, 0, 2, 3}, {1, 0, 3, 2}, {1, 2, 0, 3}, {1, 2, 3, 0}, {1, 3, 0, 2}, {1, 3, 2, 0},
    {2, 0, 1, 3}, {2, 0, 3, 1}, {2, 1, 0, 3}, {2, 1, 3, 0}, {2, 3, 0, 1}, {2, 3, 1, 0},
    {3, 0, 1, 2}, {3, 0, 2, 1}, {3, 1, 0, 2}, {3, 1, 2, 0}, {3, 2, 0, 1}, {3, 2, 1, 0}};

int log2Ceil(uint64_t n) {
  int l = 0;
  while ((uint64_t(1) << l) < n) ++l;
  return l;
}

}  // namespace

float SobolSampler::sample1D(uint64_t pixel, uint64_t sample, uint32_t dim) const {
  uint64_t key = requestKey(seed_, pixel, sample, dim);
  uint32_t index = nestedUniformScramble(uint32_t(sample), uint32_t(key));
  return fixedPointToFloat(nestedUniformScramble(sobolDimension0(index), uint32_t(key >> 32)));
}

Vec2 SobolSampler::sample2D(uint64_t pixel, uint64_t sample, uint32_t dim) const {
  uint64_t key = requestKey(seed_, pixel, sample, dim);
  uint32_t index = nestedUniformScramble(uint32_t(sample), uint32_t(key));
  uint32_t x = nestedUniformScramble(sobolDimension0(index), uint32_t(hashValues(key, 1)));
  uint32_t y = nestedUniformScramble(sobolDimension1(index), uint32_t(hashValues(key, 2)));
  return {fixedPointToFloat(x), fixedPointToFloat(y)};
}

ZSobolSampler::ZSobolSampler(uint64_t seed, int samplesPerPixel, int width, int height)
    : offImage_(seed), seed_(seed), width_(std::max(1, width)), height_(std::max(1, height)) {
  log2Spp_ = log2Ceil(uint64_t(std::max(1, samplesPerPixel)));
  int log2Res = log2Ceil(uint64_t(std::max(width_, height_)));
  nBase4Digits_ = log2Res + (log2Spp_ + 1) / 2;
}

void ZSobolSampler::start(uint64_t pixel, uint64_t sample) {
  pixel_ = pixel, sample_ = sample;
  dimension_ = 0;
  onImage_ = pixel < uint64_t(width_) * uint64_t(height_);
  if (!onImage_) return;
  uint64_t x = pixel % uint64_t(width_), y = pixel / uint64_t(width_);
  uint64_t round = sample >> log2Spp_, indexInPattern = sample & ((uint64_t(1) << log2Spp_) - 1);
  roundSeed_ = hashValues(seed_, round);
  uint64_t morton = spreadBits(uint32_t(x)) | (spreadBits(uint32_t(y)) << 1);
  mortonIndex_ = (morton << log2Spp_) | indexInPattern;
}

// Base-4 digits from the most significant; with an odd log2Spp they sit one
// bit higher and bit 0 is a final base-2 digit. A digit's permutation is keyed
// by its quadtree node: the digits above it and its position.
uint64_t ZSobolSampler::sampleIndex(uint32_t dim) const {
  uint64_t key = hashValues(roundSeed_, dim, 1);
  int odd = log2Spp_ & 1;
  uint64_t index = 0;
  for (int i = nBase4Digits_ - 1; i >= odd; --i) {
    int shift = 2 * i - odd;
    uint32_t digit = uint32_t(mortonIndex_ >> shift) & 3;
    uint64_t higher = shift + 2 < 64 ? mortonIndex_ >> (shift + 2) : 0;
    uint64_t p = hashValues(key, higher, shift) % 24;
    index |= uint64_t(DigitPermutations[p][digit]) << shift;
  }
  if (odd) index |= (mortonIndex_ & 1) ^ (hashValues(key, mortonIndex_ >> 1, 0) >> 63);
  return index;
}

float ZSobolSampler::get1D() {
  uint32_t d = dimension_++;
  if (!onImage_) return offImage_.sample1D(pixel_, sample_, d);
  uint64_t index = sampleIndex(d);
  uint32_t scramble = uint32_t(hashValues(roundSeed_, d, 2, index >> 32));
  return fixedPointToFloat(nestedUniformScramble(sobolDimension0(uint32_t(index)), scramble));
}

Vec2 ZSobolSampler::get2D() {
  uint32_t d = dimension_;
  dimension_ += 2;
  if (!onImage_) return offImage_.sample2D(pixel_, sample_, d);
  uint64_t index = sampleIndex(d);
  uint64_t scramble = hashValues(roundSeed_, d, 2, index >> 32);
  uint32_t x = nestedUniformScramble(sobolDimension0(uint32_t(index)), uint32_t(scramble));
  uint32_t y = nestedUniformScramble(sobolDimension1(uint32_t(index)), uint32_t(scramble >> 32));
  return {fixedPointToFloat(x), fixedPointToFloat(y)};
}

}  // namespace lb
