#include "integrators/guided/sd_tree.h"

#include <cmath>
#include <cstdio>
#include "integrators/guided/sphere_map.h"

namespace lb::guiding {

namespace {
class SdTreeGuide final : public DirectionGuide {
 public:
  SdTreeGuide(const SdTree& tree, float bsdfFraction) : DirectionGuide(bsdfFraction), tree_(tree) {}
  float pdf(const Vec3& wi) const override { return quad_->pdf(squareFromDirection(wi)) / FourPi; }
  Vec3 sample(Vec2 u, float* pdf) const override {
    Vec3 d = directionFromSquare(quad_->sample(u, pdf));
    *pdf /= FourPi;
    return d;
  }

 protected:
  bool prepareAt(const SurfaceInteraction& si, const BSDF&) override {
    quad_ = &tree_.samplingTree(si.p, orientationClass(si));
    return quad_->total() > 0;
  }

 private:
  const SdTree& tree_;
  const QuadTree* quad_ = nullptr;
};
}  // namespace

SdTree::SdTree(const Bounds3& b, SdTreeSettings s) : settings_(s), nodes_(1), leaves_(1) {
  Vec3 extent = b.hi - b.lo;
  float side = std::max({extent.x, extent.y, extent.z, 1e-6f}) * 1.001f;
  lo_ = b.center() - Vec3(0.5f * side);
  size_ = Vec3(side);
}

std::unique_ptr<DirectionGuide> SdTree::makeGuide(float bsdfFraction) const {
  return std::make_unique<SdTreeGuide>(*this, bsdfFraction);
}

size_t SdTree::leafOf(const Vec3& p) const {
  Vec3 c = glm::clamp((p - lo_) / size_, Vec3(0.f), Vec3(OneMinusEpsilon));
  uint32_t n = 0;
  while (nodes_[n].child[0]) {
    int a = nodes_[n].axis;
    int half = c[a] >= 0.5f;
    c[a] = std::min(2 * c[a] - float(half), OneMinusEpsilon);
    n = nodes_[n].child[half];
  }
  return nodes_[n].leaf;
}

void SdTree::learn(const TileRecords& records) {
  for (const auto& tile : records)
    for (const GuideVertex& v : tile) {
      float value = luminance(v.incident) / v.pdf;
      if (!std::isfinite(value) || !(v.pdf > 0)) continue;
      Leaf& leaf = leaves_[leafOf(v.p)];
      ++leaf.records;
      if (value > 0) leaf.building[size_t(v.orientation)].record(squareFromDirection(v.wi), value);
    }
}

// Splits while the leaf's share of records exceeds the threshold; each half
// is taken to have received half of them.
void SdTree::split(uint32_t node, int axis, float threshold) {
  size_t leafIndex = nodes_[node].leaf;
  if (float(leaves_[leafIndex].records) <= threshold) return;
  Leaf half = leaves_[leafIndex];
  half.records /= 2;
  leaves_[leafIndex] = half;
  leaves_.push_back(half);
  uint32_t a = uint32_t(nodes_.size()), b = a + 1;
  int next = (axis + 1) % 3;  // the axis the halves will split on
  nodes_.push_back({{0, 0}, uint32_t(leafIndex), next});
  nodes_.push_back({{0, 0}, uint32_t(leaves_.size() - 1), next});
  nodes_[node].child[0] = a, nodes_[node].child[1] = b, nodes_[node].axis = axis;
  split(a, next, threshold);
  split(b, next, threshold);
}

void SdTree::endIteration(int k) {
  float threshold = settings_.spatialThreshold * std::sqrt(std::pow(2.f, float(k)));
  size_t before = nodes_.size();
  for (uint32_t n = 0; n < before; ++n)
    if (!nodes_[n].child[0]) split(n, nodes_[n].axis, threshold);
  for (Leaf& leaf : leaves_) {
    for (int o = 0; o < OrientationClasses; ++o) {
      leaf.sampling[size_t(o)] = std::move(leaf.building[size_t(o)]);
      leaf.building[size_t(o)] =
          leaf.sampling[size_t(o)].refined(settings_.subdivisionThreshold, settings_.maxQuadTreeDepth);
    }
    leaf.records = 0;
  }
}

std::vector<std::string> SdTree::statistics() const {
  size_t nodes = 0;
  int deepest = 0;
  for (const Leaf& l : leaves_)
    for (const QuadTree& q : l.sampling) nodes += q.nodeCount(), deepest = std::max(deepest, q.depth());
  char line[200];
  std::snprintf(line, sizeof line,
                "sd-tree: %zu spatial leaves, %zu quadtree nodes (%.1f per leaf), deepest quadtree %d", leaves_.size(),
                nodes, double(nodes) / double(leaves_.size()), deepest);
  return {line};
}

Image SdTree::densityImage(const Vec3& p, int orientation, int height) const {
  Image img(2 * height, height);
  const QuadTree& q = samplingTree(p, orientation);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < 2 * height; ++x)
      img.at(x, y) = Color(q.pdf({(float(y) + 0.5f) / float(height), (float(x) + 0.5f) / float(2 * height)}) / FourPi);
  return img;
}

}  // namespace lb::guiding
