#include "core/film.h"
#include <limits>
#include <cmath>
#include <algorithm>

namespace lb {

void PassImage::add(int x, int y, const Color& v, uint64_t sampleIndex, Film& film) {
  if (!isFinite(v)) {
    film.recordNonFinite(x, y, sampleIndex);
    return;
  }
  value_[size_t(y) * width_ + x] += glm::dvec3(v);
}

void PassImage::splat(Vec2 raster, const Color& v, uint64_t sampleIndex, Film& film) {
  if (!filter_ || filter_->isPixelBox() || !isFinite(v)) {  // (a non-finite value is counted once)
    addAtRaster(raster, v, sampleIndex, film);
    return;
  }
  // Pixels whose centre x + ½ lies within the radius of raster.x, and in y.
  float r = filter_->radius();
  int x0 = std::max(0, int(std::ceil(raster.x - 0.5f - r))), x1 = std::min(width_ - 1, int(std::floor(raster.x - 0.5f + r)));
  int y0 = std::max(0, int(std::ceil(raster.y - 0.5f - r))), y1 = std::min(height_ - 1, int(std::floor(raster.y - 0.5f + r)));
  // The filter is separable: each column's and row's factor once (at most
  // 2·MaxRadius + 1 of each).
  float wx[2 * PixelFilter::MaxRadius + 1], wy[2 * PixelFilter::MaxRadius + 1];
  for (int x = x0; x <= x1; ++x) wx[x - x0] = filter_->normalised1D(raster.x - (float(x) + 0.5f));
  for (int y = y0; y <= y1; ++y) wy[y - y0] = filter_->normalised1D(raster.y - (float(y) + 0.5f));
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      float w = wx[x - x0] * wy[y - y0];
      if (w != 0) value_[size_t(y) * width_ + x] += glm::dvec3(v) * double(w);
    }
}

Film::Film(int width, int height)
    : width_(width), height_(height), sum_(size_t(width) * height, glm::dvec3(0)),
      sumSq_(size_t(width) * height, glm::dvec3(0)), count_(size_t(width) * height, 0),
      passSum_(size_t(width) * height, glm::dvec3(0)), passSumSq_(size_t(width) * height, glm::dvec3(0)) {}

void Film::recordNonFinite(int x, int y, uint64_t sampleIndex) {
  nonFinite_.fetch_add(1);
  std::lock_guard<std::mutex> lock(recordMutex_);
  records_.push_back({x, y, sampleIndex});
  std::sort(records_.begin(), records_.end());
  if (records_.size() > RecordedNonFinite) records_.pop_back();
}

void Film::addSample(int x, int y, uint64_t sampleIndex, Color L) {
  size_t i = index(x, y);
  if (!isFinite(L)) {
    recordNonFinite(x, y, sampleIndex);
    L = Color(0.f);
  }
  glm::dvec3 v(L);
  sum_[i] += v;
  sumSq_[i] += v * v;
  count_[i] += 1;
}

void Film::addPass(const PassImage& pass) {
  const auto& v = pass.values();
  for (size_t i = 0; i < v.size(); ++i) {
    passSum_[i] += v[i];
    passSumSq_[i] += v[i] * v[i];
  }
  ++passes_;
}

Image Film::image() const {
  Image img(width_, height_);
  for (size_t i = 0; i < sum_.size(); ++i) {
    glm::dvec3 mean = count_[i] ? sum_[i] / double(count_[i]) : glm::dvec3(0);
    if (passes_) mean += passSum_[i] / double(passes_);
    if (!progressive_.empty()) mean += progressive_[i];
    img.pixels[i] = Color(mean);
  }
  return img;
}

namespace {
glm::dvec3 meanVariance(const glm::dvec3& sum, const glm::dvec3& sumSq, double n) {
  if (n < 2) return glm::dvec3(0);
  glm::dvec3 mean = sum / n;
  return glm::max(glm::dvec3(0), (sumSq - n * mean * mean) / (n - 1)) / n;
}
}  // namespace

Image Film::varianceOfMean(size_t* overflowed) const {
  Image img(width_, height_);
  const double largest = double(std::numeric_limits<float>::max());
  size_t beyond = 0;
  for (size_t i = 0; i < sum_.size(); ++i) {
    glm::dvec3 v = meanVariance(sum_[i], sumSq_[i], double(count_[i])) +
                   meanVariance(passSum_[i], passSumSq_[i], double(passes_));
    if (!(v.x <= largest && v.y <= largest && v.z <= largest)) ++beyond;
    auto fit = [&](double c) { return float(c <= largest ? c : largest); };  // NaN (Inf - Inf) too
    img.pixels[i] = Color(fit(v.x), fit(v.y), fit(v.z));
  }
  if (overflowed) *overflowed = beyond;
  return img;
}

double Film::meanVarianceOfMean() const {
  if (passesCorrelated_) return std::nan("");
  // In double, unclamped: a variance beyond a float stays +Inf in the log
  // rather than a sum of clamped values that means nothing.
  double total = 0;
  for (size_t i = 0; i < sum_.size(); ++i) {
    glm::dvec3 v = meanVariance(sum_[i], sumSq_[i], double(count_[i])) +
                   meanVariance(passSum_[i], passSumSq_[i], double(passes_));
    total += v.x + v.y + v.z;
  }
  return sum_.empty() ? 0 : total / (3.0 * double(sum_.size()));
}

std::vector<NonFiniteSample> Film::firstNonFinite() const {
  std::lock_guard<std::mutex> lock(recordMutex_);
  return records_;
}

}  // namespace lb
