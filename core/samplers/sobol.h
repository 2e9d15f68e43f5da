#pragma once
// Owen-scrambled Sobol' points, in two orders.
//
// Both samplers only use the first two Sobol' dimensions (van der Corput and
// the Pascal-matrix dimension), which together form a (0,2)-sequence in base 2
// (Sobol' 1967; Kollig & Keller 2002, "Efficient multidimensional sampling"):
// every aligned block of 2^m consecutive points is a (0,m,2)-net. Higher
// dimensions are "padded" (Burley 2020, "Practical Hash-based Owen
// Scrambling", JCGT 9(4), §5): each 1-D or 2-D request shuffles the sample
// index and Owen-scrambles the points with keys hashed from its dimension, so
// requests are decorrelated from one another while each keeps the net
// structure. Owen scrambling (Owen 1995, "Randomly permuted (t,m,s)-nets and
// (t,s)-sequences") keeps nets nets and makes every single point uniform on
// [0,1)^s, so any sample budget is unbiased.
//
//   SobolSampler   each pixel an independent randomization (keys hash the pixel).
//   ZSobolSampler  Ahmed & Wonka 2020 (see below): one randomized sequence over
//                  the whole image, pixels taking consecutive blocks of it in a
//                  randomly permuted Morton order, which spreads the error as
//                  blue noise over the screen.
#include "core/sampler.h"

namespace lb {

// The 32 bits of v in reverse order (v's bit k moves to bit 31 − k).
uint32_t reverseBits32(uint32_t v);
// Sobol' dimension 0 as 0.32 fixed point: the van der Corput radical inverse of
// i in base 2, i.e. i's bits mirrored about the binary point.
uint32_t sobolDimension0(uint32_t i);
// Sobol' dimension 1 (primitive polynomial x + 1): the generator matrix is the
// upper-triangular Pascal matrix mod 2, whose column k (for bit k of i) is
// v_k, with v_0 = 0.1b and v_{k+1} = v_k xor (v_k >> 1).
uint32_t sobolDimension1(uint32_t i);
// Laine & Karras 2011 ("Stratified sampling for stochastic transparency"): a
// keyed bijection in which every output bit depends only on the same and lower
// input bits. Uses the improved constants of Burley 2020, listing 2 / §4.
uint32_t laineKarrasPermutation(uint32_t x, uint32_t seed);
// Owen's nested uniform scrambling of a 0.32 fixed-point value (Burley 2020 §3):
// reverse the bits so that "more significant digit" becomes "lower bit", apply
// the Laine–Karras permutation, reverse back. Each output bit is flipped by a
// hash of the seed and all the more significant bits.
uint32_t nestedUniformScramble(uint32_t x, uint32_t seed);

// 0.32 fixed point to a float in [0,1): the top 24 bits, exact (truncation
// keeps each point inside its elementary interval), never 1.
inline float fixedPointToFloat(uint32_t v) { return std::min(OneMinusEpsilon, float(v >> 8) * 0x1p-24f); }

// Padded, Owen-scrambled Sobol' (Burley 2020 §5; the idea of pbrt-v4's
// PaddedSobolSampler, without needing the sample count). A request at
// dimension d for (pixel, sample) hashes key = (seed, pixel, d), then
//   index' = nestedUniformScramble(sample, low half of key)   (the shuffle),
//   1-D:  scramble(sobolDimension0(index'), high half of key),
//   2-D:  scramble(sobolDimension0(index')), scramble(sobolDimension1(index')),
//         seeds hashValues(key, 1) and hashValues(key, 2).
// The shuffle is itself an Owen scramble of the index's bits, so it maps the
// first 2^m indices (and every aligned block of 2^m) onto an aligned block of
// 2^m Sobol' indices: prefixes of power-of-two length stay (0,m,2)-nets.
// Sample indices ≥ 2^32: the high half is hashed into the key, so each block
// of 2^32 samples is an independent randomization (still a net per block).
class SobolSampler final : public Sampler {
 public:
  explicit SobolSampler(uint64_t seed) : seed_(seed) {}
  void start(uint64_t pixel, uint64_t sample) override {
    pixel_ = pixel, sample_ = sample;
    dimension_ = 0;
  }
  float get1D() override { return sample1D(pixel_, sample_, dimension_++); }
  Vec2 get2D() override {
    Vec2 u = sample2D(pixel_, sample_, dimension_);
    dimension_ += 2;
    return u;
  }
  std::unique_ptr<Sampler> clone() const override { return std::make_unique<SobolSampler>(*this); }
  uint64_t seed() const override { return seed_; }

  // The values as pure functions of (seed, pixel, sample, dimension).
  float sample1D(uint64_t pixel, uint64_t sample, uint32_t dim) const;
  Vec2 sample2D(uint64_t pixel, uint64_t sample, uint32_t dim) const;

 private:
  uint64_t seed_, pixel_ = 0, sample_ = 0;
};

// Ahmed & Wonka 2020, "Screen-space blue-noise diffusion of Monte Carlo
// sampling error via hierarchical ordering of pixels" (SIGGRAPH Asia), in the
// form of pbrt-v4's ZSobolSampler.
//
// Pixel (x, y) of a res × res image (res the power of two ≥ width, height)
// owns the spp = 2^log2Spp consecutive indices mortonIndex = (morton(x, y) <<
// log2Spp) | s of one Sobol' sequence. Read in base 4 from the most significant
// digit, mortonIndex is a path down a quadtree over the screen (then over the
// pixel's samples); each digit is permuted by one of the 24 permutations of
// {0,1,2,3}, chosen by a hash of (the higher digits, the digit's position, the
// dimension, the round seed), i.e. an independent random permutation per
// quadtree node. Neighbouring pixels thus get different, well-stratified
// sub-blocks of one sequence, so their errors are negatively correlated (blue
// noise). With an odd log2Spp the lowest digit is base 2 and is flipped by a
// hash bit. The permuted index gives Sobol' dimensions 0 (1-D) or 0 and 1
// (2-D), Owen-scrambled with seeds hashed from (round seed, dimension); a
// pixel's spp samples are an aligned block of 2^log2Spp indices, so a full
// pattern is a (0,log2Spp,2)-net in every 2-D request.
//
// Samples beyond the pattern: round r = sample >> log2Spp repeats the pattern
// with the seed hashValues(seed, r), an independent copy. A budget that is not
// a multiple of spp stays unbiased (each sample alone is uniform) but only
// complete rounds are stratified. Pixel indices outside width × height (light
// paths) are answered exactly as SobolSampler would answer them. The Morton
// index needs 2·log2(res) + log2Spp ≤ 64 bits; Sobol' indices above 32 bits
// select the Owen scrambling seed (each 2^32 block scrambled independently).
class ZSobolSampler final : public Sampler {
 public:
  // samplesPerPixel is rounded up to a power of two (at least 1).
  ZSobolSampler(uint64_t seed, int samplesPerPixel, int width, int height);
  void start(uint64_t pixel, uint64_t sample) override;
  float get1D() override;
  Vec2 get2D() override;
  std::unique_ptr<Sampler> clone() const override { return std::make_unique<ZSobolSampler>(*this); }
  uint64_t seed() const override { return seed_; }
  int samplesPerPixel() const { return 1 << log2Spp_; }

 private:
  // The permuted Sobol' index of the current sample for dimension `dim`.
  uint64_t sampleIndex(uint32_t dim) const;

  SobolSampler offImage_;
  uint64_t seed_, pixel_ = 0, sample_ = 0, roundSeed_ = 0, mortonIndex_ = 0;
  int log2Spp_ = 0, nBase4Digits_ = 0, width_, height_;
  bool onImage_ = false;
};

}  // namespace lb
