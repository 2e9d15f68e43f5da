// The learned structures of the `guided` integrator, checked against their
// definitions: the quadtree's density integrates to 1 and is what its
// sampling follows (χ², with expected counts integrated from pdf(), a
// separate code path from sample()'s halving of the unit square); refinement
// splits exactly the quadrants above ρ of the energy; the spatial tree splits
// by the record count; Q-learning's update is the running mean of its targets
// (learning rate 1/(1 + visits)); the sphere's bins are equal-area.
#include <gtest/gtest.h>
#include "core/rng.h"
#include "integrators/guided/q_learning.h"
#include "integrators/guided/quadtree.h"
#include "integrators/guided/sd_tree.h"
#include "integrators/guided/sphere_map.h"
#include "tests/support/statistics.h"

namespace lb::test {
namespace {

using namespace lb::guiding;
constexpr double Alpha = 1e-3;

// A tree trained on a distribution with two bright spots and a dim floor,
// refined twice, then trained again (the state a sampling tree is in).
QuadTree trainedTree(int maxDepth) {
  Pcg32 rng(5, 3);
  QuadTree tree;
  for (int round = 0; round < 3; ++round) {
    for (int i = 0; i < 40000; ++i) {
      float pick = rng.next1D();
      Vec2 c = rng.next2D();
      if (pick < 0.5f)
        c = Vec2(0.3f, 0.7f) + 0.02f * c;  // a small bright spot
      else if (pick < 0.8f)
        c = Vec2(0.8f, 0.1f) + 0.1f * c;  // a larger one
      tree.record(glm::min(c, Vec2(OneMinusEpsilon)), 1.f);
    }
    if (round < 2) tree = tree.refined(0.01f, maxDepth);
  }
  return tree;
}

TEST(GuidedQuadTree, DensityIntegratesToOne) {
  // Leaves of depth ≤ 9 are unions of cells of a 512-grid: the midpoint sum is exact.
  QuadTree tree = trainedTree(9);
  ASSERT_GT(tree.depth(), 4);
  const int N = 512;
  double sum = 0;
  for (int y = 0; y < N; ++y)
    for (int x = 0; x < N; ++x) sum += tree.pdf({(x + 0.5f) / N, (y + 0.5f) / N});
  EXPECT_NEAR(sum / (N * N), 1.0, 1e-5);
}

TEST(GuidedQuadTree, SamplingFollowsTheDensity) {
  QuadTree tree = trainedTree(9);
  const int Cells = 64, Sub = 8;  // a 512-grid of midpoints integrates each cell exactly
  std::vector<double> expected(Cells * Cells, 0), observed(Cells * Cells, 0);
  const size_t Samples = 400000;
  for (int y = 0; y < Cells * Sub; ++y)
    for (int x = 0; x < Cells * Sub; ++x)
      expected[size_t((y / Sub) * Cells + x / Sub)] +=
          tree.pdf({(x + 0.5f) / (Cells * Sub), (y + 0.5f) / (Cells * Sub)}) / (Cells * Sub * Cells * Sub) * Samples;
  Pcg32 rng(9, 1);
  for (size_t i = 0; i < Samples; ++i) {
    Vec2 c = tree.sample(rng.next2D());
    ASSERT_TRUE(c.x >= 0 && c.x < 1 && c.y >= 0 && c.y < 1);
    observed[size_t(int(c.y * Cells) * Cells + int(c.x * Cells))] += 1;
  }
  Chi2Result r = chi2Test(observed, expected);
  EXPECT_TRUE(r.passed(Alpha)) << r.message << " p = " << r.pValue;
}

// ρ = 0.01 over uniform energy: quadrants hold 1/4, 1/16, 1/64 (> 0.01, split)
// and 1/256 (a leaf), so levels 1–3 are full: 1 + 4 + 16 + 64 nodes, depth 4.
TEST(GuidedQuadTree, RefinementSplitsQuadrantsAboveRho) {
  QuadTree uniform;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) uniform.record({(x + 0.5f) / 64, (y + 0.5f) / 64}, 1.f);
  QuadTree r = uniform.refined(0.01f, 20);
  EXPECT_EQ(r.nodeCount(), 85u);
  EXPECT_EQ(r.depth(), 4);
  // From a root alone, the one quadrant's new node is taken as uniform: it
  // splits like the uniform case, one level lower (1 + 1 + 4 + 16 + 64 nodes).
  QuadTree point;
  point.record({0.3f, 0.6f}, 5.f);
  EXPECT_EQ(point.refined(0.01f, 20).nodeCount(), 86u);
  // Recorded and refined again, all energy at one point leaves only the
  // nodes on its path, down to the depth limit: one node per level.
  for (int round = 0; round < 5; ++round) {
    point = point.refined(0.01f, 7);
    point.record({0.3f, 0.6f}, 5.f);
  }
  QuadTree p = point.refined(0.01f, 7);
  EXPECT_EQ(p.depth(), 7);
  EXPECT_EQ(p.nodeCount(), 7u);
  EXPECT_EQ(QuadTree().refined(0.01f, 20).nodeCount(), 1u);  // nothing recorded: the root alone
}

// The spatial tree splits a leaf while it holds more than c·√(2^k) records,
// each half taken to hold half: 10000 records at c = 1000, k = 0 split four
// times (10000 → 625), into 16 leaves.
TEST(GuidedSdTree, SplitsLeavesByRecordCount) {
  Bounds3 b;
  b.extend(Vec3(0.f)), b.extend(Vec3(1.f));
  SdTreeSettings s;
  s.spatialThreshold = 1000;
  SdTree tree(b, s);
  Pcg32 rng(2, 2);
  TileRecords records(1);
  for (int i = 0; i < 10000; ++i) {
    GuideVertex v;
    v.p = Vec3(rng.next1D(), rng.next1D(), rng.next1D());
    v.wi = Vec3(0, 0, 1), v.pdf = 1, v.incident = Color(1.f);
    records[0].push_back(v);
  }
  tree.learn(records);
  tree.endIteration(0);
  EXPECT_EQ(tree.leafCount(), 16u);
}

TEST(GuidedQLearning, UpdateIsTheRunningMeanOfTheTargets) {
  Bounds3 b;
  b.extend(Vec3(0.f)), b.extend(Vec3(2.f, 1.f, 1.f));
  QLearning q(b, {4, 4});
  TileRecords records(2);
  const float targets[] = {1, 2, 6};
  for (int i = 0; i < 3; ++i) {
    GuideVertex v;
    v.p = Vec3(0.1f, 0.1f, 0.1f), v.orientation = 2, v.wi = glm::normalize(Vec3(0.3f, 0.2f, 0.9f));
    v.emitted = targets[i] - 0.5f, v.scattered = 0.5f;  // the target is L_e + ∫ f cos Q
    records[size_t(i % 2)].push_back(v);
  }
  q.learn(records);
  int cell = q.cellOf(Vec3(0.1f)), bin = q.binOf(glm::normalize(Vec3(0.3f, 0.2f, 0.9f)));
  ASSERT_NE(q.q(cell, 2), nullptr);
  EXPECT_FLOAT_EQ(q.q(cell, 2)[bin], 3.f);
  EXPECT_EQ(q.q(cell, 3), nullptr);  // another orientation learned nothing
}

// Bins of the equal-area square cover 4π/n each: the fraction of uniform
// directions in each bin is 1/n (χ²), and each bin's centre lies in it.
TEST(GuidedQLearning, BinsAreEqualArea) {
  Bounds3 b;
  b.extend(Vec3(0.f)), b.extend(Vec3(1.f));
  QLearning q(b, {2, 6});
  std::vector<double> observed(size_t(q.bins()), 0), expected(size_t(q.bins()), 0);
  const int N = 200000;
  Pcg32 rng(4, 4);
  for (int i = 0; i < N; ++i) {
    Vec2 u = rng.next2D();
    float z = 1 - 2 * u.x, r = std::sqrt(std::max(0.f, 1 - z * z)), phi = 2 * Pi * u.y;
    observed[size_t(q.binOf({r * std::cos(phi), r * std::sin(phi), z}))] += 1;
  }
  for (int k = 0; k < q.bins(); ++k) {
    expected[size_t(k)] = double(N) / q.bins();
    EXPECT_EQ(q.binOf(q.binCenter(k)), k);
  }
  Chi2Result r = chi2Test(observed, expected);
  EXPECT_TRUE(r.passed(Alpha)) << r.message << " p = " << r.pValue;
}

}  // namespace
}  // namespace lb::test
