#include "core/film.h"
#include <algorithm>

namespace lb {

Film::Film(int width, int height)
    : width_(width), height_(height), sum_(size_t(width) * height, glm::dvec3(0)),
      sumSq_(size_t(width) * height, glm::dvec3(0)), count_(size_t(width) * height, 0),
      splat_(size_t(width) * height, glm::dvec3(0)) {}

void Film::addSample(int x, int y, uint64_t sampleIndex, Color L) {
  size_t i = index(x, y);
  if (!isFinite(L)) {
    nonFinite_.fetch_add(1);
    std::lock_guard<std::mutex> lock(recordMutex_);
    records_.push_back({x, y, sampleIndex});
    std::sort(records_.begin(), records_.end());
    if (records_.size() > RecordedNonFinite) records_.pop_back();
    L = Color(0.f);
  }
  glm::dvec3 v(L);
  sum_[i] += v;
  sumSq_[i] += v * v;
  count_[i] += 1;
}

void Film::mergeSplats(const SplatBuffer& splats) {
  for (size_t i = 0; i < splat_.size(); ++i) {
    const glm::dvec3& v = splats.sum[i];
    if (std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)) splat_[i] += v;
    else nonFinite_.fetch_add(1);
  }
}

Image Film::image() const {
  Image img(width_, height_);
  for (size_t i = 0; i < sum_.size(); ++i) {
    glm::dvec3 mean = count_[i] ? sum_[i] / double(count_[i]) : glm::dvec3(0);
    img.pixels[i] = Color(mean + splat_[i] / splatScale_);
  }
  return img;
}

Image Film::varianceOfMean() const {
  Image img(width_, height_);
  for (size_t i = 0; i < sum_.size(); ++i) {
    double n = double(count_[i]);
    if (n < 2) continue;
    glm::dvec3 mean = sum_[i] / n;
    glm::dvec3 s2 = glm::max(glm::dvec3(0), (sumSq_[i] - n * mean * mean) / (n - 1));
    img.pixels[i] = Color(s2 / n);
  }
  return img;
}

double Film::meanVarianceOfMean() const {
  Image v = varianceOfMean();
  double total = 0;
  for (const Color& c : v.pixels) total += double(c.r) + c.g + c.b;
  return v.pixels.empty() ? 0 : total / (3.0 * v.pixels.size());
}

std::vector<NonFiniteSample> Film::firstNonFinite() const {
  std::lock_guard<std::mutex> lock(recordMutex_);
  return records_;
}

}  // namespace lb
