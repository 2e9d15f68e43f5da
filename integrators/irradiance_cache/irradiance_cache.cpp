#include "integrators/irradiance_cache/irradiance_cache.h"

namespace lb {

IrradianceCache::IrradianceCache(CacheSettings settings, const Bounds3& sceneBounds)
    : settings_(settings), octree_(sceneBounds) {}

bool IrradianceCache::interpolate(const Vec3& p, const Vec3& n, const LocalRecords& local, Color& E,
                                  int segmentsLeft) const {
  // E(x) = Σ w_i E_i(x) / Σ w_i over records with w_i > 1/a (Ward 1988).
  const float minWeight = 1 / settings_.a;
  // At a record's own position w = ∞; capping it (a distance of 1e-6 R) keeps
  // coincident records averaged instead of producing ∞/∞.
  constexpr float MaxWeight = 1e6f;
  double sumW = 0;
  Color sum(0.f);
  auto consider = [&](const IrradianceRecord& r) {
    if (segmentsLeft >= 0 && r.segmentsLeft != segmentsLeft) return;  // another path-length budget
    float w = wardWeight(r, p, n);
    if (!(w > minWeight) || recordInFrontOf(r, p, n)) return;
    w = std::min(w, MaxWeight);
    sum += w * extrapolate(r, p, n, settings_.gradients);
    sumW += w;
  };
  octree_.forEachAt(p, [&](uint32_t id) { consider(records_[id]); });
  for (const IrradianceRecord& r : local.records) consider(r);
  if (sumW <= 0) return false;
  // Extrapolation can overshoot below zero where irradiance falls steeply;
  // negative irradiance is never physical.
  E = glm::max(sum / float(sumW), Color(0.f));
  return true;
}

void IrradianceCache::clampRadius(IrradianceRecord& r, float worldPerPixel) const {
  // Gradient limit (Křivánek et al. 2008): R ≤ E/|∇_t E|, so extrapolation
  // cannot move E by more than a·E within the record's reach.
  if (settings_.gradients)
    for (int c = 0; c < 3; ++c) {
      float g = glm::length(r.translationalGradient[c]);
      if (g > 0 && r.E[c] > 0) r.R = std::min(r.R, r.E[c] / g);
    }
  float scale = settings_.spacingInPixels ? worldPerPixel : 1.f;
  float reach = settings_.a * r.R;
  if (!(reach >= settings_.minSpacing * scale)) reach = settings_.minSpacing * scale;  // also catches NaN
  reach = std::min(reach, settings_.maxSpacing * scale);
  r.R = reach / settings_.a;
  r.minR = settings_.minSpacing * scale / settings_.a;
  // Where the minimum spacing enlarged R again (near corners the Ward–Heckbert
  // gradient grows like 1/distance), shrink the gradient instead, keeping
  // the same bound on the extrapolation.
  for (int c = 0; c < 3; ++c) {
    float g = glm::length(r.translationalGradient[c]);
    float limit = std::max(r.E[c], 0.f) / r.R;
    if (g > limit) r.translationalGradient[c] *= limit / g;
  }
}

void IrradianceCache::neighbourClamp(IrradianceRecord& r) {
  // Křivánek et al. 2006: R may not exceed a neighbour's R plus the distance to
  // it (the triangle inequality for distances to the nearest surface), applied
  // both ways with the records within R of the new one and the records whose
  // reach covers it (a large open-floor record overhanging a new corner record).
  auto clampPair = [&](uint32_t id) {
    IrradianceRecord& other = records_[id];
    float d = glm::length(r.p - other.p);
    // Never below a record's own minimum spacing (pixel spacing differs with depth).
    r.R = std::max(std::min(r.R, other.R + d), r.minR);
    other.R = std::max(std::min(other.R, r.R + d), other.minR);
  };
  octree_.forEachInBall(r.p, r.R, clampPair);
  octree_.forEachAt(r.p, clampPair);
}

void IrradianceCache::merge(std::vector<LocalRecords>& tiles) {
  for (LocalRecords& tile : tiles) {
    for (IrradianceRecord& r : tile.records) {
      if (!(r.R > 0) || !isFinite(r.p) || !std::isfinite(r.E.r + r.E.g + r.E.b)) continue;  // unusable
      if (settings_.neighbourClamping) neighbourClamp(r);
      records_.push_back(r);
      octree_.insert(uint32_t(records_.size() - 1), r.p, settings_.a * r.R);
    }
    tile.records.clear();
  }
}

}  // namespace lb
