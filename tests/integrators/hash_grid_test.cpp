// VCM's merging index (integrators/photon_map/hash_grid.h) against brute
// force: the same points, strictly within the radius, in ascending index,
// with the same squared distances; and the same layout whatever the thread
// count.
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include "core/rng.h"
#include "integrators/photon_map/hash_grid.h"

namespace lb::test {
namespace {

struct Hit {
  uint32_t index;
  float d2;
  bool operator==(const Hit& o) const { return index == o.index && d2 == o.d2; }
};

std::vector<Hit> bruteForce(const std::vector<Vec3>& points, Vec3 p, float r) {
  std::vector<Hit> hits;
  for (size_t i = 0; i < points.size(); ++i) {
    Vec3 d = points[i] - p;
    if (float d2 = glm::dot(d, d); d2 < r * r) hits.push_back({uint32_t(i), d2});
  }
  return hits;
}

std::vector<Hit> query(const HashGrid& grid, Vec3 p) {
  std::vector<Hit> hits;
  grid.forEachWithin(p, [&](uint32_t i, float d2) { hits.push_back({i, d2}); });
  return hits;
}

// Points on a few planes (light vertices lie on surfaces), some coincident,
// on both sides of the origin so negative cells are hashed too; queries
// near them and far away.
std::vector<Vec3> surfacePoints(Pcg32& rng, size_t n, Vec3 offset, float scale) {
  std::vector<Vec3> points;
  for (size_t i = 0; i < n; ++i) {
    float a = rng.next1D() * 2 - 1, b = rng.next1D() * 2 - 1;
    int plane = int(rng.uniformInt(3));
    Vec3 p = plane == 0 ? Vec3(a, -1, b) : plane == 1 ? Vec3(-1, a, b) : Vec3(a, b, -1);
    points.push_back(offset + scale * p);
    if (i % 97 == 0) points.push_back(points.back());  // a duplicate
  }
  return points;
}

TEST(HashGrid, FindsExactlyThePointsWithinTheRadiusInAscendingIndex) {
  Pcg32 rng(5, 7);
  int nonEmpty = 0;
  for (float scale : {1.f, 1e-3f, 1e3f})
    for (float relativeRadius : {0.001f, 0.01f, 0.1f, 0.7f}) {
      Vec3 offset(3 * scale, -2 * scale, 0.5f * scale);
      std::vector<Vec3> points = surfacePoints(rng, 20000, offset, scale);
      float r = relativeRadius * scale;
      HashGrid grid(points, r);
      for (int q = 0; q < 400; ++q) {
        // Half the queries at a point's position (merges happen there), half anywhere in the box.
        Vec3 p = q % 2 == 0 ? points[rng.uniformInt(uint32_t(points.size()))] + r * Vec3(rng.next1D() - 0.5f)
                            : offset + scale * Vec3(rng.next1D() * 2.2f - 1.1f, rng.next1D() * 2.2f - 1.1f,
                                                   rng.next1D() * 2.2f - 1.1f);
        std::vector<Hit> expected = bruteForce(points, p, r), got = query(grid, p);
        nonEmpty += expected.empty() ? 0 : 1;
        ASSERT_EQ(got, expected) << "scale " << scale << ", radius " << r << ", query " << q << ": " << got.size()
                                 << " found, " << expected.size() << " within the radius";
      }
    }
  EXPECT_GT(nonEmpty, 2000);  // the comparison is mostly of queries that find something
}

TEST(HashGrid, EmptyAndSinglePointSets) {
  HashGrid empty(std::vector<Vec3>{}, 1.f);
  EXPECT_TRUE(query(empty, Vec3(0.f)).empty());
  HashGrid one(std::vector<Vec3>{Vec3(1, 2, 3)}, 0.5f);
  EXPECT_EQ(query(one, Vec3(1.2f, 2, 3)).size(), 1u);
  EXPECT_TRUE(query(one, Vec3(1.5f, 2, 3)).empty());  // strictly within: at distance r it is not found
}

TEST(HashGrid, LayoutDoesNotDependOnTheThreadCount) {
  Pcg32 rng(11, 13);
  std::vector<Vec3> points = surfacePoints(rng, 60000, Vec3(0.f), 1);
  std::vector<std::vector<Hit>> results;
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    HashGrid grid(points, 0.02f);
    std::vector<Hit> all;
    Pcg32 queries(1, 1);
    for (int q = 0; q < 200; ++q) {
      std::vector<Hit> h = query(grid, points[queries.uniformInt(uint32_t(points.size()))]);
      all.insert(all.end(), h.begin(), h.end());
    }
    results.push_back(all);
  }
  EXPECT_EQ(results[0], results[1]);
}

}  // namespace
}  // namespace lb::test
