#pragma once
// The octree of records (Ward 1988; pbrt-v2's IrradianceCache): a record is
// stored in every node, at the depth whose size matches its reach, that
// overlaps the cube around its sphere of influence. A lookup at p walks the
// single root-to-leaf chain of nodes containing p, so it sees each candidate
// once. Visit order depends only on insertion order: lookups are
// deterministic, and concurrent lookups are safe while nothing is inserted.
#include <array>
#include <cstdint>
#include <vector>
#include "core/math.h"

namespace lb {

class RecordOctree {
 public:
  explicit RecordOctree(const Bounds3& bounds);
  // Stores record `id` whose influence is the ball (centre, radius).
  void insert(uint32_t id, const Vec3& centre, float radius);
  // visit(id) for every record whose cube may contain p.
  template <typename F>
  void forEachAt(const Vec3& p, const F& visit) const;
  // visit(id) for every record stored in a node overlapping the ball; a
  // record may be visited more than once. Used for neighbour clamping.
  template <typename F>
  void forEachInBall(const Vec3& centre, float radius, const F& visit) const;
  size_t nodeCount() const { return nodes_.size(); }

 private:
  static constexpr int MaxDepth = 16;
  struct Node {
    std::array<int32_t, 8> children;
    std::vector<uint32_t> records;
    Node() { children.fill(-1); }
  };
  void insert(int node, const Bounds3& nodeBounds, int depth, uint32_t id, const Bounds3& box, float diagonal2);
  template <typename F>
  void ballRecurse(int node, const Bounds3& nodeBounds, const Vec3& c, float r2, const F& visit) const;
  static Bounds3 childBounds(const Bounds3& b, int child);
  std::vector<Node> nodes_;
  Bounds3 bounds_;
};

inline Bounds3 RecordOctree::childBounds(const Bounds3& b, int child) {
  Vec3 mid = b.center();
  Bounds3 c;
  c.lo = Vec3(child & 1 ? mid.x : b.lo.x, child & 2 ? mid.y : b.lo.y, child & 4 ? mid.z : b.lo.z);
  c.hi = Vec3(child & 1 ? b.hi.x : mid.x, child & 2 ? b.hi.y : mid.y, child & 4 ? b.hi.z : mid.z);
  return c;
}

template <typename F>
void RecordOctree::forEachAt(const Vec3& p, const F& visit) const {
  Bounds3 b = bounds_;
  if (p.x < b.lo.x || p.y < b.lo.y || p.z < b.lo.z || p.x > b.hi.x || p.y > b.hi.y || p.z > b.hi.z) return;
  int node = 0;
  while (node >= 0) {
    for (uint32_t id : nodes_[node].records) visit(id);
    Vec3 mid = b.center();
    int child = (p.x > mid.x ? 1 : 0) | (p.y > mid.y ? 2 : 0) | (p.z > mid.z ? 4 : 0);
    b = childBounds(b, child);
    node = nodes_[node].children[child];
  }
}

template <typename F>
void RecordOctree::forEachInBall(const Vec3& centre, float radius, const F& visit) const {
  ballRecurse(0, bounds_, centre, radius * radius, visit);
}

template <typename F>
void RecordOctree::ballRecurse(int node, const Bounds3& b, const Vec3& c, float r2, const F& visit) const {
  Vec3 nearest = glm::clamp(c, b.lo, b.hi);
  if (glm::dot(nearest - c, nearest - c) > r2) return;
  for (uint32_t id : nodes_[node].records) visit(id);
  for (int child = 0; child < 8; ++child)
    if (nodes_[node].children[child] >= 0) ballRecurse(nodes_[node].children[child], childBounds(b, child), c, r2, visit);
}

}  // namespace lb
