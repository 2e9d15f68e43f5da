#include "integrators/irradiance_cache/record_octree.h"

namespace lb {

RecordOctree::RecordOctree(const Bounds3& bounds) : bounds_(bounds) {
  // A cube slightly larger than the scene, so records on its boundary fit.
  Vec3 c = bounds.center();
  float half = 0.5f * maxComponent(bounds.hi - bounds.lo);
  if (!isFinite(c) || !std::isfinite(half)) c = Vec3(0.f), half = 0;  // empty scene
  half = half > 0 ? half * 1.01f : 1.f;
  bounds_.lo = c - Vec3(half), bounds_.hi = c + Vec3(half);
  nodes_.emplace_back();
}

void RecordOctree::insert(uint32_t id, const Vec3& centre, float radius) {
  if (!isFinite(centre) || !(radius >= 0) || !std::isfinite(radius)) return;  // never findable
  Bounds3 box;
  box.lo = centre - Vec3(radius), box.hi = centre + Vec3(radius);
  insert(0, bounds_, 0, id, box, glm::dot(box.hi - box.lo, box.hi - box.lo));
}

void RecordOctree::insert(int node, const Bounds3& b, int depth, uint32_t id, const Bounds3& box, float diagonal2) {
  // Stop where a child would be smaller than the record's cube.
  Vec3 half = 0.5f * (b.hi - b.lo);
  if (depth == MaxDepth || glm::dot(half, half) < diagonal2) {
    nodes_[node].records.push_back(id);
    return;
  }
  Vec3 mid = b.center();
  for (int child = 0; child < 8; ++child) {
    // Does the child's octant overlap the record's cube?
    if ((child & 1 ? box.hi.x <= mid.x : box.lo.x > mid.x) || (child & 2 ? box.hi.y <= mid.y : box.lo.y > mid.y) ||
        (child & 4 ? box.hi.z <= mid.z : box.lo.z > mid.z))
      continue;
    if (nodes_[node].children[child] < 0) {
      nodes_[node].children[child] = int32_t(nodes_.size());
      nodes_.emplace_back();  // may reallocate: index, never hold references across this
    }
    insert(nodes_[node].children[child], childBounds(b, child), depth + 1, id, box, diagonal2);
  }
}

}  // namespace lb
