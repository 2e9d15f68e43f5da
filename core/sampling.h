#pragma once
// Warps from the unit square to common domains, each with its density, plus MIS
// heuristics (Veach 1997, §9.2) and a discrete distribution for light selection.
#include <vector>
#include "core/math.h"

namespace lb {

// Shirley–Chiu concentric map, pdf 1/π on the unit disc.
inline Vec2 sampleConcentricDisk(Vec2 u) {
  Vec2 o = 2.f * u - Vec2(1.f);
  if (o.x == 0 && o.y == 0) return {0, 0};
  float r, theta;
  if (std::abs(o.x) > std::abs(o.y)) r = o.x, theta = (Pi / 4) * (o.y / o.x);
  else r = o.y, theta = Pi / 2 - (Pi / 4) * (o.x / o.y);
  return r * Vec2(std::cos(theta), std::sin(theta));
}

// Malley's method: pdf cosθ/π on the +z hemisphere.
inline Vec3 sampleCosineHemisphere(Vec2 u) {
  Vec2 d = sampleConcentricDisk(u);
  // At the disc's rim x² + y² can round to 1: z = 0 would be a direction on
  // the horizon, of density 0, drawn about once in 10⁷ samples. Lifted just
  // above it instead, so every sample has the density it is drawn with.
  return {d.x, d.y, std::max(safeSqrt(1 - d.x * d.x - d.y * d.y), 1e-7f)};
}
inline float cosineHemispherePdf(float cosTheta) { return cosTheta > 0 ? cosTheta * InvPi : 0.f; }

inline Vec3 sampleUniformHemisphere(Vec2 u) {
  float z = u.x, r = safeSqrt(1 - z * z), phi = 2 * Pi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float uniformHemispherePdf() { return Inv2Pi; }

inline Vec3 sampleUniformSphere(Vec2 u) {
  float z = 1 - 2 * u.x, r = safeSqrt(1 - z * z), phi = 2 * Pi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float uniformSpherePdf() { return Inv4Pi; }

// Uniform over the cone of directions with cosθ >= cosThetaMax around +z.
inline Vec3 sampleUniformCone(Vec2 u, float cosThetaMax) {
  float cosTheta = (1 - u.x) + u.x * cosThetaMax;
  float sinTheta = safeSqrt(1 - cosTheta * cosTheta), phi = 2 * Pi * u.y;
  return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}
inline float uniformConePdf(float cosThetaMax) { return 1 / (2 * Pi * (1 - cosThetaMax)); }

// Barycentrics uniform over a triangle (Heitz 2019's low-distortion map is not
// needed here; the square-root map is exact and simple).
inline Vec2 sampleUniformTriangle(Vec2 u) {
  float su = std::sqrt(u.x);
  return {1 - su, u.y * su};
}

inline float balanceHeuristic(float pdfA, float pdfB) { return pdfA / (pdfA + pdfB); }
inline float powerHeuristic(float pdfA, float pdfB) {
  if (std::isinf(pdfA)) return 1.f;
  float a = pdfA * pdfA, b = pdfB * pdfB;
  return a / (a + b);
}

// Piecewise-constant discrete distribution (light selection, triangle picking).
class DiscreteDistribution {
 public:
  DiscreteDistribution() = default;
  explicit DiscreteDistribution(const std::vector<float>& weights);
  bool empty() const { return pmf_.empty(); }
  size_t size() const { return pmf_.size(); }
  float total() const { return total_; }
  float pmf(size_t i) const { return pmf_[i]; }
  // Picks an index; `u` is remapped to a fresh uniform number (sample reuse).
  size_t sample(float u, float* pmf = nullptr, float* uRemapped = nullptr) const;

 private:
  std::vector<float> pmf_, cdf_;
  float total_ = 0;
};

}  // namespace lb
