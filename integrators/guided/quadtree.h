#pragma once
// The directional quadtree ("D-tree") of practical path guiding (Müller,
// Gross, Novák 2017, §3.3): a density over the square of sphere_map.h, so
// over the sphere of directions. Each node splits its square into four
// quadrants and keeps the energy recorded in each; a quadrant without a child
// node is a leaf of constant density. Recording adds a value to every node on
// the way down to the leaf containing the point; sampling walks down choosing
// quadrants in proportion to their energy, so
//
//   p(c) = Π over the levels of 4 · energy(quadrant) / energy(node)
//
// over the square (the leaf is uniform), and p(ω) = p(c) / 4π.
//
// Refinement (§3.4): from one iteration's energies a new structure is built in
// which every quadrant holding more than a fraction ρ of the total energy is
// split (up to a depth limit) and the others are leaves; its energies start at
// zero for the next iteration to fill.
#include <array>
#include <cstdint>
#include <vector>
#include "core/math.h"

namespace lb::guiding {

class QuadTree {
 public:
  QuadTree() : nodes_(1) {}

  void record(Vec2 c, float value);
  float total() const;
  // The density over the unit square (uniform where nothing was recorded).
  float pdf(Vec2 c) const;
  // A point drawn from the density, and (if asked) its density there.
  Vec2 sample(Vec2 u, float* pdf = nullptr) const;
  // The structure the energies call for, with zero energies (see above).
  QuadTree refined(float rho, int maxDepth) const;

  size_t nodeCount() const { return nodes_.size(); }
  int depth() const;

 private:
  struct Node {
    std::array<float, 4> energy{};    // quadrant q = x-half + 2·y-half
    std::array<uint32_t, 4> child{};  // 0: the quadrant is a leaf
  };
  int depth(uint32_t node) const;
  std::vector<Node> nodes_;  // nodes_[0]: the root, the whole square
};

}  // namespace lb::guiding
