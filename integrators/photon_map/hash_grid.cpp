// HashGrid's parallel counting-sort build (hash_grid.h).
#include "integrators/photon_map/hash_grid.h"
#include <tbb/parallel_for.h>

namespace lb {

void HashGrid::build(const std::vector<Vec3>& points, float radius) {
  const size_t n = points.size();
  radius2_ = radius * radius;
  invCell_ = 1 / (2 * radius);
  buckets_ = std::max<size_t>(1, n);
  order_.assign(n, 0);
  points_.resize(n);
  start_.assign(buckets_ + 1, 0);
  if (n == 0) return;
  // A fixed number of blocks, not one per thread: the layout must not depend
  // on the thread count. (Each holds a count per bucket: 4 of them cost
  // 16 bytes a point, a tenth of what the light vertices themselves take.)
  const size_t blocks = std::min<size_t>(4, (n + 4095) / 4096);
  const size_t perBlock = (n + blocks - 1) / blocks;
  std::vector<uint32_t> bucket(n);
  std::vector<std::vector<uint32_t>> counts(blocks);
  tbb::parallel_for(size_t(0), blocks, [&](size_t k) {
    counts[k].assign(buckets_, 0);
    for (size_t i = k * perBlock; i < std::min(n, (k + 1) * perBlock); ++i) {
      glm::ivec3 c = cellOf(points[i]);
      bucket[i] = bucketOf(c.x, c.y, c.z);
      ++counts[k][bucket[i]];
    }
  });
  // Exclusive prefix sum over (bucket, block): block k's first slot in bucket b.
  uint32_t total = 0;
  for (size_t b = 0; b < buckets_; ++b) {
    start_[b] = total;
    for (size_t k = 0; k < blocks; ++k) {
      uint32_t c = counts[k][b];
      counts[k][b] = total;
      total += c;
    }
  }
  start_[buckets_] = total;
  tbb::parallel_for(size_t(0), blocks, [&](size_t k) {
    for (size_t i = k * perBlock; i < std::min(n, (k + 1) * perBlock); ++i) {
      uint32_t slot = counts[k][bucket[i]]++;
      order_[slot] = uint32_t(i);
      points_[slot] = points[i];
    }
  });
}

}  // namespace lb
