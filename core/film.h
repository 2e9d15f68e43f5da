#pragma once
// Film: per-pixel accumulation of camera-path samples with a running variance,
// plus a splat buffer for light-tracing contributions. Non-finite samples never
// reach the image: they are counted, replaced by zero, and the first few are
// recorded with their pixel and sample index so they can be replayed.
//
// Determinism: a pixel's samples are added by one thread, in sample order, and
// splat buffers are merged in a fixed order, so the sums do not depend on the
// thread count.
#include <atomic>
#include <mutex>
#include <vector>
#include "core/image.h"

namespace lb {

struct NonFiniteSample {
  int x, y;
  uint64_t sampleIndex;
  bool operator<(const NonFiniteSample& o) const {
    return std::tie(sampleIndex, y, x) < std::tie(o.sampleIndex, o.y, o.x);
  }
};

// Light-tracing splats of one worker, merged into the film in a fixed order.
struct SplatBuffer {
  int width = 0, height = 0;
  std::vector<glm::dvec3> sum;
  SplatBuffer(int w, int h) : width(w), height(h), sum(size_t(w) * size_t(h), glm::dvec3(0)) {}
  void add(Vec2 raster, const Color& v) {
    int x = std::min(int(raster.x), width - 1), y = std::min(int(raster.y), height - 1);
    sum[size_t(y) * width + x] += glm::dvec3(v);
  }
};

class Film {
 public:
  Film(int width, int height);
  int width() const { return width_; }
  int height() const { return height_; }

  // Thread-safe for distinct pixels.
  void addSample(int x, int y, uint64_t sampleIndex, Color L);
  void mergeSplats(const SplatBuffer& splats);
  // Splats are divided by this (e.g. the number of light paths per pixel).
  void setSplatScale(double scale) { splatScale_ = scale; }

  uint64_t samples(int x, int y) const { return count_[index(x, y)]; }
  Image image() const;
  // Per-pixel variance of the pixel mean, per channel: s²/n.
  Image varianceOfMean() const;
  double meanVarianceOfMean() const;  // over pixels and channels

  uint64_t nonFiniteCount() const { return nonFinite_.load(); }
  std::vector<NonFiniteSample> firstNonFinite() const;
  static constexpr size_t RecordedNonFinite = 8;

 private:
  size_t index(int x, int y) const { return size_t(y) * width_ + x; }
  int width_, height_;
  std::vector<glm::dvec3> sum_, sumSq_;
  std::vector<uint64_t> count_;
  std::vector<glm::dvec3> splat_;
  double splatScale_ = 1;
  std::atomic<uint64_t> nonFinite_{0};
  mutable std::mutex recordMutex_;
  std::vector<NonFiniteSample> records_;
};

}  // namespace lb
