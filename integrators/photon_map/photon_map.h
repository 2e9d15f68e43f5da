#pragma once
// Photons and their lookups (Jensen 1996, 2001). The kd-tree is FLANN's
// single kd-tree index (exact search, leaf size 10): the project's declared
// dependency for nearest-neighbour queries; measured against FLANN's
// randomised forest in the benchmark (README). Queries are read-only and
// thread-safe.
#include <flann/flann.hpp>
#include <memory>
#include <vector>
#include "core/interaction.h"
#include "core/math.h"

namespace lb {

struct Photon {
  Vec3 p;       // where it landed
  Vec3 wi;      // unit direction towards where it came from
  Color power;  // flux carried, already divided by the number of emitted photons
  Vec3 n;       // geometric normal of the surface it landed on
  int segments; // path segments from the light to here (1: straight from the light)
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

  // Reflected radiance at a surface point x (Jensen's estimate over the k
  // nearest photons): Σ f(wo, ω_p) Φ_p K(d_p) |ω_p·n_s|/|ω_p·n_g| with the
  // chosen filter K over the disc of radius r (the k-th neighbour's distance,
  // at most maxRadius). `f(wi)` evaluates the BSDF for a photon arriving from
  // wi. Only photons of at most `maxSegments` segments count (path_length.h:
  // a camera path of j segments reaching x may use photons of max_depth − j).
  // Photons whose surface normal differs from x's by more than 60° are
  // ignored (they lie on another surface, e.g. across a corner).
  //
  // Normalisation (k-th neighbour). For a locally uniform photon density λ,
  // π r_k² λ ~ Gamma(k, 1), so E[1/(π r_k²)] = λ/(k − 1) and k photons over
  // π r_k² overestimate by k/(k − 1) (+3.4 % at k = 30). Given r_k, the k − 1
  // nearer photons are uniform in the disc, so summing only them with
  // weights of mean 1 over the disc is unbiased: the photon that sets the
  // radius only measures it. (The cone and Epanechnikov kernels give it
  // weight 0 anyway; the box must leave it out.) With fewer than k photons
  // within maxRadius the disc is fixed and all of them count; given n ≥ k
  // photons in that disc, E[(k − 1)/(π r_k²)] = n/(π maxRadius²), so the two
  // cases together are exactly unbiased for uniform density.
  //
  // Shading normals. Photons land with an area density set by the geometry:
  // their flux per unit area is ∫ L_i |ω·n_g| dω (the photon's β carries the
  // adjoint correction of Veach 1997 Eq. 5.19 at earlier vertices, which
  // makes it exactly this geometric flux). Reflected radiance is
  // ∫ f L_i |ω·n_s| dω (the convention of the path tracer, f·|wi·n_s|), so
  // each photon is weighted by |ω_p·n_s(x)| / |ω_p·n_g(photon)|.
  //
  // Known biases, vanishing as r → 0 with more photons: the boundary bias
  // (the disc reaches past a surface's edge, where no photons land, so the
  // estimate darkens near edges and corners) and the proximity bias (light
  // varying within r is blurred; a caustic's edge spreads by about r). With
  // a fixed disc (k larger than any count: the `k: 0` setting) the blur
  // conserves energy: the estimate integrates over a flat surface to the
  // flux that landed. The k-nearest disc does not: near a caustic sharper
  // than r_k, dark points' discs reach into the bright core and their
  // 1/r_k² adds light, so a sharp caustic's pixels read high (+6 % on the
  // glass sphere's at 2.5e5 caustic photons, +2 % at 4e6;
  // consistent_caustic_test.cpp), shrinking as r_k does.
  template <typename F>
  Color radiance(const SurfaceInteraction& x, const DensityQuery& q, int maxSegments, const F& f,
                 std::vector<std::pair<size_t, float>>& scratch) const;

 private:
  std::vector<Photon> photons_;
  std::unique_ptr<PointIndex> index_;
  double buildSeconds_ = 0;
};

template <typename F>
Color PhotonMap::radiance(const SurfaceInteraction& x, const DensityQuery& q, int maxSegments, const F& f,
                          std::vector<std::pair<size_t, float>>& scratch) const {
  if (photons_.empty() || maxSegments < 1) return Color(0.f);
  index_->knn(x.p, q.k, q.maxRadius, scratch);
  if (scratch.empty()) return Color(0.f);
  // With fewer than k photons inside maxRadius the disc is the whole maxRadius;
  // otherwise the last photon found sets r and is left out (see above).
  bool fixedDisc = scratch.size() < q.k && std::isfinite(q.maxRadius);
  float r2 = fixedDisc ? q.maxRadius * q.maxRadius : scratch.back().second;
  if (!(r2 > 0)) return Color(0.f);
  size_t count = fixedDisc ? scratch.size() : scratch.size() - 1;
  float r = std::sqrt(r2);
  Color sum(0.f);
  for (size_t j = 0; j < count; ++j) {
    const Photon& ph = photons_[scratch[j].first];
    if (ph.segments > maxSegments || glm::dot(ph.n, x.ng) < 0.5f) continue;  // too long; cos 60°
    float cosG = absDot(ph.wi, ph.n);
    if (cosG == 0) continue;
    float d2 = scratch[j].second, w;
    switch (q.filter) {
      case PhotonFilter::Cone: w = (1 - std::sqrt(d2) / r) / (1 - 2.f / 3.f); break;  // Jensen's cone, k = 1
      case PhotonFilter::Epanechnikov: w = 2 * (1 - d2 / r2); break;
      default: w = 1;
    }
    sum += f(ph.wi) * ph.power * (w * absDot(ph.wi, x.shading.n) / cosG);
  }
  return sum / (Pi * r2);
}

}  // namespace lb
