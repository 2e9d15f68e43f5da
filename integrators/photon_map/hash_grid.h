#pragma once
// A hashed uniform grid for fixed-radius queries, rebuilt every iteration
// (VCM's and bidirectional photon mapping's light vertices; SmallVCM's
// HashGrid, Georgiev et al. 2012). Cells are 2r wide and each point is in
// exactly one of them, so the ball of radius r around a query overlaps at
// most 2 × 2 × 2 cells: the ones nearest to it along each axis.
//
// The build is a counting sort of the points by bucket, in parallel: each of
// a few blocks of points counts its buckets, one prefix sum over (bucket,
// block) gives every block its slots, and each block scatters its points in
// order. A bucket therefore lists its points in ascending index whatever the
// thread count, and queries visit them in a fixed order (bit-identical
// images). O(n) work, no allocation per cell.
#include <algorithm>
#include <cstdint>
#include <vector>
#include "core/math.h"

namespace lb {

class HashGrid {
 public:
  HashGrid() = default;
  HashGrid(const std::vector<Vec3>& points, float radius) { build(points, radius); }
  void build(const std::vector<Vec3>& points, float radius);

  // Calls found(index, squared distance) for every point strictly within the
  // radius of p (as FLANN's radius search), in ascending index.
  template <typename Found>
  void forEachWithin(const Vec3& p, Found&& found) const;

 private:
  uint32_t bucketOf(int x, int y, int z) const {
    // Teschner et al. 2003's spatial hash.
    return ((uint32_t(x) * 73856093u) ^ (uint32_t(y) * 19349663u) ^ (uint32_t(z) * 83492791u)) % uint32_t(buckets_);
  }
  glm::ivec3 cellOf(const Vec3& p) const { return glm::ivec3(glm::floor(p * invCell_)); }

  float radius2_ = 0, invCell_ = 0;
  size_t buckets_ = 1;
  std::vector<uint32_t> start_;   // bucket b's points are order_[start_[b] … start_[b + 1])
  std::vector<uint32_t> order_;   // point indices sorted by bucket, ascending within one
  std::vector<Vec3> points_;      // in order_'s order: the distance test reads them sequentially
};

template <typename Found>
void HashGrid::forEachWithin(const Vec3& p, Found&& found) const {
  if (order_.empty()) return;
  // The cell corner nearest to p: the 2×2×2 cells around it hold every point within r (cell = 2r).
  Vec3 c = p * invCell_;
  glm::ivec3 lo = glm::ivec3(glm::floor(c - Vec3(0.5f)));
  uint32_t buckets[8];
  int n = 0;
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        uint32_t b = bucketOf(lo.x + dx, lo.y + dy, lo.z + dz);
        bool seen = false;  // two cells may share a bucket: read it once
        for (int k = 0; k < n; ++k) seen |= buckets[k] == b;
        if (!seen) buckets[n++] = b;
      }
  // The points within r, bucket by bucket, then in ascending index: each
  // bucket lists its points in ascending index, so one bucket needs no sort,
  // and a handful found in several is sorted cheaply (a k-way merge of the
  // buckets' lists instead cost a comparison per bucket for every point
  // scanned, about 15 scanned for each one found).
  thread_local std::vector<std::pair<uint32_t, float>> within;
  within.clear();
  for (int k = 0; k < n; ++k)
    for (uint32_t slot = start_[buckets[k]], end = start_[buckets[k] + 1]; slot < end; ++slot) {
      Vec3 d = points_[slot] - p;
      float d2 = glm::dot(d, d);
      if (d2 < radius2_) within.push_back({order_[slot], d2});
    }
  if (n > 1) std::sort(within.begin(), within.end());
  for (const auto& [index, d2] : within) found(index, d2);
}

}  // namespace lb
