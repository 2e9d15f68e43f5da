#include "integrators/guided/quadtree.h"

#include <algorithm>

namespace lb::guiding {

namespace {
// The quadrant holding c, and c in that quadrant's own unit square.
int quadrant(Vec2& c) {
  int qx = c.x >= 0.5f, qy = c.y >= 0.5f;
  c = glm::min(2.f * c - Vec2(float(qx), float(qy)), Vec2(OneMinusEpsilon));
  return qx + 2 * qy;
}
}  // namespace

void QuadTree::record(Vec2 c, float value) {
  for (uint32_t n = 0;;) {
    int q = quadrant(c);
    nodes_[n].energy[size_t(q)] += value;
    if (!nodes_[n].child[size_t(q)]) return;
    n = nodes_[n].child[size_t(q)];
  }
}

float QuadTree::total() const {
  const auto& e = nodes_[0].energy;
  return e[0] + e[1] + e[2] + e[3];
}

// Sampling picks the x-half with probability (e0 + e2) / Σ e, then the
// y-half within it, each with one coordinate rescaled to its half: the same
// quadrant probabilities as the product above, without a 1-D search, and one
// bit of each coordinate spent per level as the square shrinks by one bit.
float QuadTree::pdf(Vec2 c) const {
  float p = 1;
  for (uint32_t n = 0;;) {
    const auto& e = nodes_[n].energy;
    float sum = e[0] + e[1] + e[2] + e[3];
    int q = quadrant(c);
    if (!(sum > 0)) return p;  // nothing recorded below: uniform
    p *= 4 * e[size_t(q)] / sum;
    if (!nodes_[n].child[size_t(q)] || p == 0) return p;
    n = nodes_[n].child[size_t(q)];
  }
}

Vec2 QuadTree::sample(Vec2 u, float* pdf) const {
  glm::dvec2 uu(u);
  glm::dvec2 origin(0), size(1);
  double density = 1;
  for (uint32_t n = 0;;) {
    const auto& e = nodes_[n].energy;
    double sum = double(e[0]) + e[1] + e[2] + e[3];
    double left = sum > 0 ? (double(e[0]) + e[2]) / sum : 0.5;  // P(x-half 0)
    int qx = uu.x >= left;
    uu.x = qx ? (uu.x - left) / (1 - left) : uu.x / left;
    double lowY = qx ? double(e[1]) : double(e[0]), highY = qx ? double(e[3]) : double(e[2]);
    double bottom = lowY + highY > 0 ? lowY / (lowY + highY) : 0.5;  // P(y-half 0 | x-half)
    int qy = uu.y >= bottom;
    uu.y = qy ? (uu.y - bottom) / (1 - bottom) : uu.y / bottom;
    size *= 0.5;
    origin += glm::dvec2(qx, qy) * size;
    if (sum > 0) density *= 4 * double(e[size_t(qx + 2 * qy)]) / sum;
    uint32_t child = nodes_[n].child[size_t(qx + 2 * qy)];
    if (!child || !(sum > 0)) break;
    n = child;
  }
  if (pdf) *pdf = float(density);
  glm::dvec2 c = origin + glm::clamp(uu, 0.0, 1.0) * size;
  return glm::min(Vec2(c), Vec2(OneMinusEpsilon));
}

QuadTree QuadTree::refined(float rho, int maxDepth) const {
  QuadTree out;
  float all = total();
  if (!(all > 0)) return out;
  // (node in this tree or 0 for a new one, its node in `out`, its energy, depth)
  struct Item {
    uint32_t from, to;
    float energy;
    int depth;
  };
  std::vector<Item> stack = {{0, 0, all, 1}};
  while (!stack.empty()) {
    Item it = stack.back();
    stack.pop_back();
    for (size_t q = 0; q < 4; ++q) {
      // A new node's quadrants share its energy equally (it was a leaf).
      bool known = it.from || it.depth == 1;
      float e = known ? nodes_[it.from].energy[q] : it.energy / 4;
      if (it.depth >= maxDepth || !(e > rho * all)) continue;
      uint32_t child = uint32_t(out.nodes_.size());
      out.nodes_.push_back({});
      out.nodes_[it.to].child[q] = child;
      uint32_t fromChild = known ? nodes_[it.from].child[q] : 0;
      stack.push_back({fromChild, child, e, it.depth + 1});
    }
  }
  return out;
}

int QuadTree::depth(uint32_t n) const {
  int d = 0;
  for (uint32_t c : nodes_[n].child)
    if (c) d = std::max(d, depth(c));
  return d + 1;
}
int QuadTree::depth() const { return depth(0); }

}  // namespace lb::guiding
