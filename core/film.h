#pragma once
// Film: the image estimate and its variance, from two kinds of contributions.
//  * Camera samples (path tracing): addSample(x, y, i, L) keeps a per-pixel
//    mean and sample variance.
//  * Whole passes (light tracing, BDPT): a PassImage holds one estimate per
//    pixel for one pass — its camera-side contributions plus every splat of
//    that pass's light paths; addPass() keeps the mean and variance over
//    passes. With one light path per pixel per pass, a pixel's splat total is
//    already normalised (references.md: pixels / light paths = 1 per pass).
// Non-finite values never reach the image: they are counted, replaced by
// zero, and the first few are recorded with pixel and sample index.
//
// Determinism: a pixel's samples are added by one thread in sample order, and
// a pass's splats are added in a fixed order (tile by tile), so the sums do not
// depend on the thread count.
#include <algorithm>
#include <atomic>
#include <mutex>
#include <vector>
#include "core/filter.h"
#include "core/image.h"

namespace lb {

struct NonFiniteSample {
  int x, y;
  uint64_t sampleIndex;
  bool operator<(const NonFiniteSample& o) const {
    return std::tie(sampleIndex, y, x) < std::tie(o.sampleIndex, o.y, o.x);
  }
};

class Film;

// One pass of a splatting integrator. add() is not thread-safe: camera-side
// contributions go to a pixel owned by one tile, splats are collected per tile
// and added afterwards in tile order.
class PassImage {
 public:
  // `filter`: the camera's (core/filter.h), which splat() uses; it must
  // outlive the PassImage. None: the one-pixel box.
  PassImage(int width, int height, const PixelFilter* filter = nullptr)
      : width_(width), height_(height), value_(size_t(width) * height, glm::dvec3(0)), filter_(filter) {}
  int width() const { return width_; }
  int height() const { return height_; }
  // Adds to pixel (x, y); non-finite values are reported to `film` and dropped.
  void add(int x, int y, const Color& v, uint64_t sampleIndex, Film& film);
  // Adds to the pixel that contains `raster` (clamped to the image).
  void addAtRaster(Vec2 raster, const Color& v, uint64_t sampleIndex, Film& film) {
    add(std::clamp(int(raster.x), 0, width_ - 1), std::clamp(int(raster.y), 0, height_ - 1), v, sampleIndex, film);
  }
  // A splat at `raster` (light tracing, BDPT's t = 1): each pixel whose
  // filter reaches it gets f̂(raster − centre)·v (core/filter.h says why this
  // estimates what the camera's filtered samples do). With the one-pixel box
  // this is addAtRaster.
  void splat(Vec2 raster, const Color& v, uint64_t sampleIndex, Film& film);
  const std::vector<glm::dvec3>& values() const { return value_; }

 private:
  int width_, height_;
  std::vector<glm::dvec3> value_;
  const PixelFilter* filter_;
};

// A splat recorded by a worker, applied later in a fixed order.
struct Splat {
  Vec2 raster;
  Color value;
};

class Film {
 public:
  Film(int width, int height);
  int width() const { return width_; }
  int height() const { return height_; }

  // Thread-safe for distinct pixels.
  void addSample(int x, int y, uint64_t sampleIndex, Color L);
  void addPass(const PassImage& pass);
  // A consistent estimator's current estimate that is not an average of
  // independent samples (SPPM's photon term): added to the image as is; its
  // variance is unknown and not included in varianceOfMean().
  void setProgressiveEstimate(std::vector<glm::dvec3> estimate) { progressive_ = std::move(estimate); }

  // Passes that are not independent (a Markov chain's successive mutations,
  // integrators/mlt/mlt.h): their spread says nothing about the error, so
  // meanVarianceOfMean() is NaN ("unknown") from then on.
  void markPassesCorrelated() { passesCorrelated_ = true; }
  bool passesCorrelated() const { return passesCorrelated_; }

  uint64_t samples(int x, int y) const { return count_[index(x, y)]; }
  uint64_t passes() const { return passes_; }
  Image image() const;
  // Per-pixel variance of the pixel estimate, per channel: s²/n for each kind
  // of contribution (an integrator uses one kind).
  // Channels beyond a float's range (a pixel of 1e22 has a variance of
  // ~1e44) are written as the largest float, and counted in `overflowed`,
  // so no +Inf reaches an image (issue 34).
  Image varianceOfMean(size_t* overflowed = nullptr) const;
  double meanVarianceOfMean() const;  // over pixels and channels; NaN if passesCorrelated()

  // Thread-safe.
  void recordNonFinite(int x, int y, uint64_t sampleIndex);
  uint64_t nonFiniteCount() const { return nonFinite_.load(); }
  std::vector<NonFiniteSample> firstNonFinite() const;
  static constexpr size_t RecordedNonFinite = 8;

 private:
  size_t index(int x, int y) const { return size_t(y) * width_ + x; }
  int width_, height_;
  std::vector<glm::dvec3> sum_, sumSq_;
  std::vector<uint64_t> count_;
  std::vector<glm::dvec3> passSum_, passSumSq_;
  uint64_t passes_ = 0;
  bool passesCorrelated_ = false;
  std::vector<glm::dvec3> progressive_;
  std::atomic<uint64_t> nonFinite_{0};
  mutable std::mutex recordMutex_;
  std::vector<NonFiniteSample> records_;
};

}  // namespace lb
