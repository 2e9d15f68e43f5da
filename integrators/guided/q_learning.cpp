#include "integrators/guided/q_learning.h"

#include <algorithm>
#include <cstdio>
#include "integrators/guided/sphere_map.h"

namespace lb::guiding {

namespace {

// A table guides only once it has had this many updates per bin on average:
// a table learned from a handful of paths is a few spikes wherever those
// paths happened to find light, and sampling half the directions from it
// costs more variance than it saves.
constexpr uint64_t MinVisitsPerBin = 4;

// The distribution at one vertex: its cell's and orientation's cumulative
// table of Q·cos (q_learning.h), built after each pass's learning. The
// pointer is valid until the next learn(): a guide is prepared again at
// every vertex, and learning happens only between passes.
class QGuide final : public DirectionGuide {
 public:
  QGuide(const QLearning& table, float bsdfFraction) : DirectionGuide(bsdfFraction), table_(table) {}

  float pdf(const Vec3& wi) const override {
    int k = table_.binOf(wi);
    float w = cdf_[k] - (k > 0 ? cdf_[k - 1] : 0.f);
    return w / total() * float(table_.bins()) / FourPi;
  }

  Vec3 sample(Vec2 u, float* pdf) const override {
    const int n = table_.bins();
    float target = u.x * total();
    // The first bin whose cumulative weight exceeds the target has weight > 0;
    // if rounding put the target at the total, the last bin of weight > 0.
    int k = int(std::upper_bound(cdf_, cdf_ + n, target) - cdf_);
    if (k == n)
      for (k = n - 1; k > 0 && cdf_[k] == cdf_[k - 1];) --k;
    float before = k > 0 ? cdf_[k - 1] : 0.f;
    float inBin = std::clamp((target - before) / (cdf_[k] - before), 0.f, OneMinusEpsilon);
    int row = k / table_.cols(), col = k % table_.cols();
    *pdf = (cdf_[k] - before) / total() * float(n) / FourPi;
    return directionFromSquare(
        {(float(row) + inBin) / float(table_.rows()), (float(col) + u.y) / float(table_.cols())});
  }

  // Σ_k Q_k cos θ_k over the bins facing out of the surface.
  float total() const { return cdf_[table_.bins() - 1]; }

 protected:
  bool prepareAt(const SurfaceInteraction& si, const BSDF&) override {
    cdf_ = table_.cdf(table_.cellOf(si.p), orientationClass(si));
    return cdf_ && total() > 0;
  }

 private:
  const QLearning& table_;
  const float* cdf_ = nullptr;
};

}  // namespace

QLearning::QLearning(const Bounds3& b, QLearningSettings s) : lo_(b.lo), rows_(s.rows), cols_(2 * s.rows) {
  Vec3 extent = glm::max(b.hi - b.lo, Vec3(1e-6f));
  float longest = std::max({extent.x, extent.y, extent.z});
  for (int a = 0; a < 3; ++a) res_[a] = std::max(1, int(std::lround(float(s.gridResolution) * extent[a] / longest)));
  cellSize_ = extent / Vec3(float(res_[0]), float(res_[1]), float(res_[2]));
  for (int k = 0; k < bins(); ++k)
    centers_.push_back(
        directionFromSquare({(float(k / cols_) + 0.5f) / float(rows_), (float(k % cols_) + 0.5f) / float(cols_)}));
  slot_.assign(size_t(res_[0]) * size_t(res_[1]) * size_t(res_[2]) * OrientationClasses, -1);
}

size_t QLearning::tableOf(int cell, int orientation) {
  int32_t& slot = slot_[size_t(cell) * OrientationClasses + size_t(orientation)];
  if (slot < 0) {
    slot = int32_t(q_.size() / size_t(bins()));
    q_.resize(q_.size() + size_t(bins()), 0.f);
    visits_.resize(q_.size(), 0);
    slotOrientation_.push_back(orientation);
  }
  return size_t(slot);
}

int QLearning::cellOf(const Vec3& p) const {
  int i[3];
  for (int a = 0; a < 3; ++a) i[a] = std::clamp(int((p[a] - lo_[a]) / cellSize_[a]), 0, res_[a] - 1);
  return (i[2] * res_[1] + i[1]) * res_[0] + i[0];
}

int QLearning::binOf(const Vec3& w) const {
  Vec2 c = squareFromDirection(w);
  return std::min(int(c.x * float(rows_)), rows_ - 1) * cols_ + std::min(int(c.y * float(cols_)), cols_ - 1);
}

void QLearning::setQ(int cell, int orientation, const std::vector<float>& values) {
  size_t table = tableOf(cell, orientation);
  std::copy(values.begin(), values.end(), q_.begin() + std::ptrdiff_t(table * size_t(bins())));
  buildTables();
}

// Each table's cumulative Q·cos θ over the bins facing out of its
// orientation's axis (the class's normal, guiding_method.h), so a vertex
// looks its distribution up instead of weighting every bin.
void QLearning::buildTables() {
  cdf_.resize(q_.size());
  valueTotal_.resize(slotOrientation_.size());
  for (size_t slot = 0; slot < slotOrientation_.size(); ++slot) {
    int o = slotOrientation_[slot];
    Vec3 axis(0.f);
    axis[o / 2] = o % 2 ? -1.f : 1.f;
    uint64_t visits = 0;
    for (int k = 0; k < bins(); ++k) visits += visits_[slot * size_t(bins()) + size_t(k)];
    bool guides = visits >= MinVisitsPerBin * uint64_t(bins());
    float sum = 0;
    for (int k = 0; k < bins(); ++k) {
      float cosine = glm::dot(centers_[size_t(k)], axis);
      if (cosine > 0) sum += q_[slot * size_t(bins()) + size_t(k)] * cosine;
      cdf_[slot * size_t(bins()) + size_t(k)] = guides ? sum : 0.f;
    }
    valueTotal_[slot] = sum;
  }
}

std::unique_ptr<DirectionGuide> QLearning::makeGuide(float bsdfFraction) const {
  return std::make_unique<QGuide>(*this, bsdfFraction);
}

// (4π/n) Σ_k f(−ω → ω_k) |cos θ_k| Q(y, ω_k): the Bellman target's integral.
// (Computed from y itself, not from the guide prepared there: a table that
// does not guide yet, for want of updates, still has a value to pass back.)
float QLearning::scatteredValue(const SurfaceInteraction& y, const BSDF& bsdf) const {
  if (bsdf.flags() & BSDFSpecular) return 0;  // not guided, not propagated (q_learning.h)
  int cell = cellOf(y.p), orientation = orientationClass(y);
  const float* qy = q(cell, orientation);
  if (!qy) return 0;  // nothing learned at y
  float binArea = FourPi / float(bins());
  bool lambertian = bsdf.flags() == (BSDFReflection | BSDFDiffuse);
  if (lambertian) {  // f is constant: the sum is the table's Σ Q cos (about its class's axis)
    Vec3 n = bsdf.shadingNormal();
    if (glm::dot(y.wo, n) < 0) n = -n;  // two-sided: f on the side the path arrived from
    return binArea * valueTotal_[size_t(slot_[size_t(cell) * OrientationClasses + size_t(orientation)])] *
           luminance(bsdf.eval(y.wo, n, TransportMode::Radiance).f);
  }
  float sum = 0;
  for (int k = 0; k < bins(); ++k)
    if (qy[k] > 0)
      sum += qy[k] * luminance(bsdf.eval(y.wo, centers_[size_t(k)], TransportMode::Radiance).f) *
             absDot(centers_[size_t(k)], bsdf.shadingNormal());
  return binArea * sum;
}

void QLearning::learn(const TileRecords& records) {
  for (const auto& tile : records)
    for (const GuideVertex& v : tile) {
      size_t i = tableOf(cellOf(v.p), v.orientation) * size_t(bins()) + size_t(binOf(v.wi));
      float target = v.emitted + v.scattered;
      if (!std::isfinite(target)) continue;
      // α = 1 / (1 + visits): the running mean of the targets.
      q_[i] += (target - q_[i]) / float(++visits_[i]);
      ++updates_;
    }
  buildTables();
}

std::vector<std::string> QLearning::statistics() const {
  size_t cells = size_t(res_[0]) * size_t(res_[1]) * size_t(res_[2]), tables = q_.size() / size_t(bins());
  char line[240];
  std::snprintf(
      line, sizeof line,
      "q-learning: grid %d x %d x %d, %d bins per table, %zu tables learned (of %zu cells x %d orientations), "
      "%llu updates",
      res_[0], res_[1], res_[2], bins(), tables, cells, OrientationClasses, (unsigned long long)updates_);
  return {line};
}

// The density the guide samples there: the table's Q·cos shares (0 while
// the table does not guide yet).
Image QLearning::densityImage(const Vec3& p, int orientation, int height) const {
  Image img(2 * height, height);
  const float* c = cdf(cellOf(p), orientation);
  float total = c ? c[bins() - 1] : 0.f;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < 2 * height; ++x) {
      int k = binOf(directionFromSquare({(float(y) + 0.5f) / float(height), (float(x) + 0.5f) / float(2 * height)}));
      float w = total > 0 ? c[k] - (k > 0 ? c[k - 1] : 0.f) : 0.f;
      img.at(x, y) = Color(total > 0 ? w / total * float(bins()) / FourPi : 0.f);
    }
  return img;
}

}  // namespace lb::guiding
