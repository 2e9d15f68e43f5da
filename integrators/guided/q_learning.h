#pragma once
// Q-learning path guiding (Dahm & Keller 2017, "Learning light transport the
// reinforced way"). The rendering equation read as a Bellman equation: the
// radiance Q(x, ω) arriving at x from direction ω satisfies
//
//   Q(x, ω) = L_e(y, −ω) + ∫ f(ω_i, y, −ω) |cos θ_i| Q(y, ω_i) dω_i,   y = h(x, ω)
//
// (their Eq. 5), and is learned by temporal-difference updates toward the
// right-hand side, with the integral taken over the discretised directions at
// y (their Eq. 6):
//
//   Q(x, ω) ← (1 − α) Q(x, ω) + α (L_e(y, −ω) + (4π/n) Σ_k f(ω_k, y, −ω) |cos θ_k| Q(y, ω_k)),
//   α = 1 / (1 + visits(x, ω))        (their learning rate, §4)
//
// so each Q is the running mean of its targets. With next-event estimation,
// L_e enters the target times the MIS weight the emission got when the
// direction hit it: light that NEE finds is not learned (guided.cpp); without
// NEE, the weight is 1 and the target is the paper's. Q lives in a uniform grid of
// cells over the scene's bounds (`grid_resolution` cells along the longest
// axis), each with a table per surface orientation (guiding_method.h) of
// n = 2·rows² bins of the equal-area square (sphere_map.h): rows of cos θ,
// twice as many columns of φ, in world space (the sphere, so transmission is
// guided too). Tables are allocated when first updated.
//
// Sampling at x: a bin in proportion to Q(x, ω_k)·cos θ_k over the bins that
// face out of the surface (the paper's Q·f·cos product for a Lambertian
// surface; the BSDF component of the mixture covers the rest, transmission
// included), then a point uniformly within the bin: p(ω) = w_k / Σ w · n / 4π.
// The cosine is taken about the orientation class's axis, not the exact
// normal, so each table's cumulative weights are built once after each pass
// rather than at every vertex; directions of a bin that fall below the actual
// surface are wasted, not biased.
//
// The learned value of a Lambertian y, (4π/n) Σ f cos Q, reuses the table's
// total (f is constant); other BSDFs evaluate f at every bin's centre.
// A bin is a point estimate of its integral, so Q is a biased estimate of the
// incident radiance — which costs variance, never bias: the image is the
// mixture estimator's (direction_guide.h). Delta BSDFs are not guided and
// contribute no learned value (a mirror's Q(y, ·) is not propagated).
#include <vector>
#include "core/math.h"
#include "integrators/guided/guiding_method.h"

namespace lb::guiding {

struct QLearningSettings {
  int gridResolution = 32;  // cells along the scene's longest axis
  int rows = 8;             // cos θ rows; 2·rows φ columns; n = 2·rows² bins
};

class QLearning final : public GuidingMethod {
 public:
  QLearning(const Bounds3& sceneBounds, QLearningSettings settings);

  std::unique_ptr<DirectionGuide> makeGuide(float bsdfFraction) const override;
  float scatteredValue(const SurfaceInteraction& y, const BSDF& bsdf) const override;
  void learn(const TileRecords& records) override;
  std::vector<std::string> statistics() const override;
  Image densityImage(const Vec3& p, int orientation, int height) const override;

  // The grid and the bins (public for the tests).
  int cellOf(const Vec3& p) const;
  int binOf(const Vec3& w) const;
  int bins() const { return rows_ * cols_; }
  int rows() const { return rows_; }
  int cols() const { return cols_; }
  const Vec3& binCenter(int k) const { return centers_[size_t(k)]; }
  // The Q table of a cell and orientation, null if never updated.
  const float* q(int cell, int orientation) const {
    int32_t slot = slot_[size_t(cell) * OrientationClasses + size_t(orientation)];
    return slot < 0 ? nullptr : &q_[size_t(slot) * size_t(bins())];
  }
  // Its cumulative sampling weights (q_learning.cpp), null likewise.
  const float* cdf(int cell, int orientation) const {
    int32_t slot = slot_[size_t(cell) * OrientationClasses + size_t(orientation)];
    return slot < 0 ? nullptr : &cdf_[size_t(slot) * size_t(bins())];
  }
  // Sets a table's values directly (tests).
  void setQ(int cell, int orientation, const std::vector<float>& values);

 private:
  Vec3 lo_, cellSize_;
  int res_[3];
  int rows_, cols_;
  std::vector<Vec3> centers_;                 // each bin's central direction
  size_t tableOf(int cell, int orientation);  // allocates on first use
  void buildTables();
  std::vector<int32_t> slot_;  // per cell and orientation: its table in q_, or −1
  std::vector<float> q_;       // tables × bins
  std::vector<uint32_t> visits_;
  std::vector<float> cdf_;            // tables × bins, cumulative Q·cos (0 while a table does not guide)
  std::vector<float> valueTotal_;     // per table, Σ Q·cos (for the learned value, gate or not)
  std::vector<int> slotOrientation_;  // each table's orientation class
  uint64_t updates_ = 0;
};

}  // namespace lb::guiding
