#pragma once
// Optimal multiple importance sampling for two techniques (Kondapaneni,
// Vévoda, Grittmann, Skřivan, Slusallek & Křivánek 2019, "Optimal Multiple
// Importance Sampling", ACM TOG 38(4)): the weights that minimise the
// variance of the combined estimator among all weights that sum to 1,
//     w_i(x) = α_i p_i(x)/f(x) + n_i p_i(x)/S(x) · (1 − Σ_k α_k p_k(x)/f(x)),
//     S(x) = Σ_k n_k p_k(x),
// where α solves the linear system A α = b,
//     A_ik = ∫ p_i p_k / S dx,     b_i = ∫ f p_i / S dx.
// With these weights the multi-sample estimator becomes
//     F = Σ_i α_i + Σ_i Σ_j [f(X_ij) − Σ_k α_k p_k(X_ij)] / S(X_ij),
// the balance heuristic plus the densities as control variates: for any α
// fixed before the samples are drawn its expectation is ∫ f, because each
// density integrates to 1. α = 0 is the balance heuristic.
//
// Two things the formula assumes and a renderer does not give:
//  * A technique may produce no sample (a BSDF sample below the horizon, a
//    light sample facing away): its density then integrates to m_i < 1, and
//    the constant Σ_i α_i would be off by Σ_i α_i (1 − m_i). We use instead
//    α_i s_i with s_i = 1 if technique i produced a sample this round, 0 if
//    not, whose expectation is exactly α_i m_i, so F stays unbiased for any α
//    (the variance this adds is that of a coin of probability m_i).
//  * A and b are unknown. The paper estimates them per pixel from the
//    pixel's own samples, Â_ik = Σ_X p_i p_k / S², b̂_i = Σ_X f p_i / S²
//    (sums over the samples X of every technique, each drawn from its own
//    p_i, so Σ_X g/S estimates ∫ g), and with α solved from the same
//    samples the estimate collapses to Σ_i α_i: consistent, biased. We solve
//    for the α of a pixel's camera sample from the pixel's *earlier* samples
//    only, so every sample is unbiased given the ones before it (their
//    errors are uncorrelated; the image is unbiased at any sample count).
//
// f is a colour: A depends only on the densities, so one matrix serves the
// three channels, each with its own b and α.
#include <array>
#include <glm/glm.hpp>
#include "core/math.h"

namespace lb {

// Light sampling and BSDF sampling, one sample each per round (n_i = 1).
constexpr int OmisTechniques = 2;

// One sample X of either technique: the integrand and both techniques'
// densities at X, in one measure (ratios of densities do not depend on it).
struct OmisSample {
  Color f{0.f};
  std::array<float, OmisTechniques> p{0.f, 0.f};
  double mixture() const { return double(p[0]) + double(p[1]); }  // S(X) with n = 1
};

// α for each technique, per colour channel.
using OmisAlpha = std::array<glm::dvec3, OmisTechniques>;

// The running sums Â and b̂ of one pixel.
class OptimalMisSums {
 public:
  void record(const OmisSample& x) {
    double S = x.mixture();
    if (!(S > 0)) return;
    glm::dvec3 f(x.f.r, x.f.g, x.f.b);
    for (int i = 0; i < OmisTechniques; ++i) {
      double pi = x.p[i] / S;
      b_[i] += f * (pi / S);
      for (int k = i; k < OmisTechniques; ++k) a_[i][k] += pi * (x.p[k] / S);
    }
    a_[1][0] = a_[0][1];
  }
  void countRound() { ++rounds_; }
  uint64_t rounds() const { return rounds_; }

  // α = Â⁻¹ b̂ (Cramer's rule: the system is 2×2). Â is a Gram matrix, so
  // singular only when the two densities are proportional at every sample
  // recorded (or one technique never produced one): then α = 0, the
  // balance heuristic, which any α may be replaced by without bias.
  OmisAlpha solve() const {
    double det = a_[0][0] * a_[1][1] - a_[0][1] * a_[1][0];
    if (!(det > 1e-9 * a_[0][0] * a_[1][1])) return {glm::dvec3(0), glm::dvec3(0)};
    return {(a_[1][1] * b_[0] - a_[0][1] * b_[1]) / det, (a_[0][0] * b_[1] - a_[1][0] * b_[0]) / det};
  }
  // Â α − b̂ for channel c: the residual a test checks against rounding.
  glm::dvec2 residual(const OmisAlpha& alpha, int c) const {
    glm::dvec2 r;
    for (int i = 0; i < OmisTechniques; ++i) r[i] = a_[i][0] * alpha[0][c] + a_[i][1] * alpha[1][c] - b_[i][c];
    return r;
  }
  double a(int i, int k) const { return a_[i][k]; }
  const glm::dvec3& b(int i) const { return b_[i]; }

 private:
  double a_[OmisTechniques][OmisTechniques] = {{0, 0}, {0, 0}};
  glm::dvec3 b_[OmisTechniques] = {glm::dvec3(0), glm::dvec3(0)};
  uint64_t rounds_ = 0;
};

// One round's estimate: `samples` holds the samples the techniques produced
// (at most one each), `produced[i]` whether technique i produced one:
//     F = Σ_i α_i s_i + Σ_X (f(X) − Σ_k α_k p_k(X)) / S(X).
inline glm::dvec3 optimalMisEstimate(const OmisAlpha& alpha, const OmisSample* samples, int count,
                                     const std::array<bool, OmisTechniques>& produced) {
  glm::dvec3 F(0);
  for (int i = 0; i < OmisTechniques; ++i)
    if (produced[i]) F += alpha[i];
  for (int j = 0; j < count; ++j) {
    const OmisSample& x = samples[j];
    double S = x.mixture();
    if (!(S > 0)) continue;
    glm::dvec3 g = glm::dvec3(x.f.r, x.f.g, x.f.b) - alpha[0] * double(x.p[0]) - alpha[1] * double(x.p[1]);
    F += g / S;
  }
  return F;
}

}  // namespace lb
