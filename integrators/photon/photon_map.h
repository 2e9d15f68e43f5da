#pragma once
// Photons and their lookups (Jensen 1996, 2001). The kd-tree is FLANN's
// single kd-tree index (exact search, leaf size 10): the project's declared
// dependency for nearest-neighbour queries; measured against FLANN's
// randomised forest in the benchmark (README). Queries are read-only and
// thread-safe.
#include <flann/flann.hpp>
#include <memory>
#include <vector>
#include "core/math.h"

namespace lb {

struct Photon {
  Vec3 p;       // where it landed
  Vec3 wi;      // unit direction towards where it came from
  Color power;  // flux carried, already divided by the number of emitted photons
  Vec3 n;       // geometric normal of the surface it landed on
};

// FLANN kd-tree over 3-D points (photons or SPPM visible points).
class PointIndex {
 public:
  PointIndex() = default;
  explicit PointIndex(const std::vector<Vec3>& points);
  PointIndex(const PointIndex&) = delete;
  size_t size() const { return count_; }
  // Up to k nearest points within maxRadius; returns (index, squared distance), nearest first.
  void knn(const Vec3& q, size_t k, float maxRadius, std::vector<std::pair<size_t, float>>& out) const;
  // All points within radius (FLANN takes the squared radius).
  void radius(const Vec3& q, float radius, std::vector<std::pair<size_t, float>>& out) const;

 private:
  std::vector<float> coords_;  // FLANN keeps a pointer: the data must outlive the index
  std::unique_ptr<flann::Index<flann::L2_Simple<float>>> index_;
  size_t count_ = 0;
};

enum class PhotonFilter { Box, Cone, Epanechnikov };

struct DensityQuery {
  size_t k = 50;
  float maxRadius = Infinity;
  PhotonFilter filter = PhotonFilter::Cone;
};

class PhotonMap {
 public:
  PhotonMap() = default;
  explicit PhotonMap(std::vector<Photon> photons);
  size_t size() const { return photons_.size(); }
  const std::vector<Photon>& photons() const { return photons_; }
  double buildSeconds() const { return buildSeconds_; }
  size_t memoryBytes() const { return photons_.size() * (sizeof(Photon) + 3 * sizeof(float)); }

  // Reflected radiance at a surface point (Jensen's estimate over the k
  // nearest photons): Σ f(wo, ω_p) Φ_p K(d_p) with the chosen filter K over the
  // disc of radius r (the k-th neighbour's distance, at most maxRadius).
  // `f(wi)` evaluates the BSDF for a photon arriving from wi. Photons whose
  // surface normal differs from n by more than 60° are ignored (they lie on
  // another surface, e.g. across a corner).
  // Known biases, vanishing as r → 0 with more photons: the boundary bias
  // (the disc reaches past a surface's edge, where no photons land, so the
  // estimate darkens near edges and corners) and the proximity bias (light
  // varying within r is blurred; a caustic's edge spreads by about r).
  template <typename F>
  Color radiance(const Vec3& p, const Vec3& n, const DensityQuery& q, const F& f,
                 std::vector<std::pair<size_t, float>>& scratch) const;

 private:
  std::vector<Photon> photons_;
  std::unique_ptr<PointIndex> index_;
  double buildSeconds_ = 0;
};

template <typename F>
Color PhotonMap::radiance(const Vec3& p, const Vec3& n, const DensityQuery& q, const F& f,
                          std::vector<std::pair<size_t, float>>& scratch) const {
  if (photons_.empty()) return Color(0.f);
  index_->knn(p, q.k, q.maxRadius, scratch);
  if (scratch.empty()) return Color(0.f);
  // With fewer than k photons inside maxRadius the disc is the whole maxRadius.
  float r2 = scratch.size() < q.k && std::isfinite(q.maxRadius) ? q.maxRadius * q.maxRadius : scratch.back().second;
  if (!(r2 > 0)) return Color(0.f);
  float r = std::sqrt(r2);
  Color sum(0.f);
  for (const auto& [i, d2] : scratch) {
    const Photon& ph = photons_[i];
    if (glm::dot(ph.n, n) < 0.5f) continue;  // cos 60°
    float w;
    switch (q.filter) {
      case PhotonFilter::Cone: w = (1 - std::sqrt(d2) / r) / (1 - 2.f / 3.f); break;  // Jensen's cone, k = 1
      case PhotonFilter::Epanechnikov: w = 2 * (1 - d2 / r2); break;
      default: w = 1;
    }
    sum += f(ph.wi) * ph.power * w;
  }
  return sum / (Pi * r2);
}

}  // namespace lb
