#pragma once
// Points hashed into a uniform grid for fixed-radius queries: each point sits
// in every cell its radius ball overlaps, so a query reads the one cell it
// falls in (pbrt-v3 §16.2.3). The candidates are a superset of the points
// whose ball holds the query: the caller filters by distance. Used by SPPM
// (visible points, each with its own radius) and VCM (light vertices, one
// merging radius); the alternative is PointIndex's FLANN range search.
#include <algorithm>
#include <vector>
#include "core/math.h"

namespace lb {

class PointGrid {
 public:
  // One radius per point; cellSize should be about the largest radius.
  PointGrid(const std::vector<Vec3>& points, const std::vector<float>& radius, float cellSize)
      : cell_(cellSize), buckets_(std::max<size_t>(1, points.size())) {
    for (size_t i = 0; i < points.size(); ++i) insert(uint32_t(i), points[i], radius[i]);
  }
  // The same radius for all points, and cells of that size.
  PointGrid(const std::vector<Vec3>& points, float radius)
      : cell_(radius), buckets_(std::max<size_t>(1, points.size())) {
    for (size_t i = 0; i < points.size(); ++i) insert(uint32_t(i), points[i], radius);
  }
  // Indices of the points whose ball may hold p, ascending.
  const std::vector<uint32_t>& candidates(const Vec3& p) const { return buckets_[hash(cellOf(p))]; }

 private:
  void insert(uint32_t i, const Vec3& p, float radius) {
    glm::ivec3 lo = cellOf(p - Vec3(radius)), hi = cellOf(p + Vec3(radius));
    for (int z = lo.z; z <= hi.z; ++z)
      for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
          // Two cells of one point may hash to the same bucket: store it once,
          // or a query there would find it twice.
          auto& bucket = buckets_[hash({x, y, z})];
          if (bucket.empty() || bucket.back() != i) bucket.push_back(i);
        }
  }
  glm::ivec3 cellOf(const Vec3& p) const { return glm::ivec3(glm::floor(p / cell_)); }
  size_t hash(glm::ivec3 c) const {
    return size_t((uint32_t(c.x) * 73856093u) ^ (uint32_t(c.y) * 19349663u) ^ (uint32_t(c.z) * 83492791u)) %
           buckets_.size();
  }
  float cell_;
  std::vector<std::vector<uint32_t>> buckets_;
};

}  // namespace lb
