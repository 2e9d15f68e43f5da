#pragma once
// Practical path guiding (Müller, Gross, Novák 2017): an SD-tree, a binary
// tree over space (§3.2) whose leaves each hold a directional quadtree
// (quadtree.h) of the radiance arriving there.
//
//  * Space: the scene's bounds made a cube; a node splits its box in half
//    along x, y, z in turn. After iteration k, a leaf that received more than
//    c·√(2^k) records in that iteration is split, both halves starting from a
//    copy of its quadtree (c = `spatial_threshold`, 12000 in the paper).
//  * Directions: each leaf keeps, per surface orientation (guiding_method.h), two quadtrees, the one sampled during an
//    iteration and the one being built from its records. A record adds the
//    luminance of the incident radiance estimate divided by the density of the
//    direction that found it, L_i / p(ω), which is what makes the recorded
//    energy of a region an estimate of ∫ L_i over it (their §4). L_i is what
//    the rest of the path brought back, so an emitter the direction hit
//    counts with its MIS weight against the vertex's own light samples:
//    light that NEE finds there is not learned. After the
//    iteration the built tree is sampled, and a refined, empty structure
//    (ρ = `subdivision_threshold`, depth ≤ `max_quadtree_depth`) is built.
//  * Iterations (§5): iteration k renders 2^k samples per pixel; the
//    `guided` integrator trains in its preprocess (so in the time budget) and
//    renders every pass of the final image with the last iteration's trees,
//    as the paper's final iteration; the training images are discarded.
#include <array>
#include <vector>
#include "integrators/guided/guiding_method.h"
#include "integrators/guided/quadtree.h"

namespace lb::guiding {

struct SdTreeSettings {
  int trainingIterations = 5;          // iterations of 1, 2, 4, … spp before the final image
  float spatialThreshold = 12000;      // c
  float subdivisionThreshold = 0.01f;  // ρ
  int maxQuadTreeDepth = 20;
};

class SdTree final : public GuidingMethod {
 public:
  SdTree(const Bounds3& sceneBounds, SdTreeSettings settings);

  std::unique_ptr<DirectionGuide> makeGuide(float bsdfFraction) const override;
  void learn(const TileRecords& records) override;
  // After iteration k: split space, then rebuild every leaf's quadtrees.
  void endIteration(int k);
  std::vector<std::string> statistics() const override;
  Image densityImage(const Vec3& p, int orientation, int height) const override;

  // The quadtree sampled at p, for a surface of that orientation (guiding_method.h).
  const QuadTree& samplingTree(const Vec3& p, int orientation) const {
    return leaves_[leafOf(p)].sampling[size_t(orientation)];
  }
  size_t leafCount() const { return leaves_.size(); }

 private:
  struct Leaf {
    std::array<QuadTree, OrientationClasses> sampling, building;
    uint64_t records = 0;  // records into `building` this iteration
  };
  struct Node {
    uint32_t child[2] = {0, 0};  // both 0: a leaf
    uint32_t leaf = 0;           // its index in leaves_, for a leaf
    int axis = 0;                // the axis it splits (a leaf: will split) along
  };
  size_t leafOf(const Vec3& p) const;
  void split(uint32_t node, int axis, float threshold);

  SdTreeSettings settings_;
  Vec3 lo_, size_;           // the cube
  std::vector<Node> nodes_;  // nodes_[0]: the root
  std::vector<Leaf> leaves_;
};

}  // namespace lb::guiding
