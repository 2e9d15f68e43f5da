#include "integrators/irradiance_cache/record.h"
#include <vector>

namespace lb {

float wardWeight(const IrradianceRecord& r, const Vec3& p, const Vec3& n) {
  float denom = glm::length(p - r.p) / r.R + safeSqrt(1 - glm::dot(n, r.n));
  return 1 / denom;
}

bool recordInFrontOf(const IrradianceRecord& r, const Vec3& p, const Vec3& n) {
  return glm::dot(p - r.p, 0.5f * (n + r.n)) < -0.01f * r.R;
}

Color extrapolate(const IrradianceRecord& r, const Vec3& p, const Vec3& n, bool gradients) {
  if (!gradients) return r.E;
  Vec3 rotation = glm::cross(r.n, n), offset = p - r.p;
  Color E = r.E;
  for (int c = 0; c < 3; ++c)
    E[c] += glm::dot(rotation, r.rotationalGradient[c]) + glm::dot(offset, r.translationalGradient[c]);
  return E;
}

IrradianceRecord computeRecord(const Vec3& p, const Vec3& n, HemisphereStrata strata, Pcg32& rng,
                               const std::function<Ray(const Vec3&)>& spawn, const IncidentRadiance& incident) {
  const int M = strata.theta, N = strata.phi;
  const Frame frame(n);
  std::vector<Color> L(size_t(M) * N);
  std::vector<float> invDist(size_t(M) * N);  // 1/r, 0 for escaped rays
  auto at = [N](int j, int k) { return size_t(j) * N + k; };

  IrradianceRecord rec;
  rec.p = p, rec.n = n;
  Vec3 rotational[3] = {Vec3(0.f), Vec3(0.f), Vec3(0.f)};
  double sumInvDist = 0;
  for (int j = 0; j < M; ++j)
    for (int k = 0; k < N; ++k) {
      // Stratum (j, k): sin²θ ∈ [j/M, (j+1)/M), φ ∈ [2πk/N, 2π(k+1)/N): equal cosine-weighted measure.
      Vec2 u = rng.next2D();
      float sin2 = (j + u.x) / M, sinTheta = std::sqrt(sin2), cosTheta = safeSqrt(1 - sin2);
      float phi = 2 * Pi * (k + u.y) / N;
      Vec3 local(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta);
      IncidentSample s = incident(spawn(frame.toWorld(local)), at(j, k));
      L[at(j, k)] = s.L;
      // 1/r, finite even for a (never expected) zero or NaN distance.
      invDist[at(j, k)] = s.distance > 0 ? std::min(1e30f, 1 / s.distance) : 0.f;
      sumInvDist += invDist[at(j, k)];
      rec.E += s.L;
      // Rotational gradient (Ward & Heckbert 1992): tilting n about an in-plane
      // axis a changes cosθ by sinθ (a·v_φ), v_φ the azimuthal direction; over
      // cosine-weighted samples that is tanθ L v_φ per sample.
      if (cosTheta > 0) {
        Vec3 v(-std::sin(phi), std::cos(phi), 0);
        for (int c = 0; c < 3; ++c) rotational[c] += v * (sinTheta / cosTheta * s.L[c]);
      }
    }
  float cellMeasure = Pi / float(M * N);  // projected solid angle of one stratum
  rec.E *= cellMeasure;
  rec.R = sumInvDist > 0 ? float(double(M * N) / sumInvDist) : Infinity;

  // Translational gradient (Ward & Heckbert 1992, in the form of Křivánek et
  // al.'s 2008 course notes): moving x shifts each boundary between strata by
  // an angle ∝ 1/r of the nearer surface on either side, trading radiance
  // between neighbouring strata.
  Vec3 translational[3] = {Vec3(0.f), Vec3(0.f), Vec3(0.f)};
  for (int k = 0; k < N; ++k) {
    float phiCentre = 2 * Pi * (k + 0.5f) / N, phiEdge = 2 * Pi * k / N;
    Vec3 u(std::cos(phiCentre), std::sin(phiCentre), 0);    // across θ boundaries
    Vec3 v(-std::sin(phiEdge), std::cos(phiEdge), 0);       // across the φ boundary at φ_k
    int kPrev = (k + N - 1) % N;
    for (int j = 0; j < M; ++j) {
      if (j > 0) {  // boundary between θ strata j−1 and j, at sin²θ = j/M
        float sin2 = float(j) / M;
        float scale = 2 * Pi / N * std::sqrt(sin2) * (1 - sin2) * std::max(invDist[at(j, k)], invDist[at(j - 1, k)]);
        for (int c = 0; c < 3; ++c) translational[c] += u * (scale * (L[at(j, k)][c] - L[at(j - 1, k)][c]));
      }
      // boundary between φ strata k−1 and k over θ stratum j
      float scale = (std::sqrt(float(j + 1) / M) - std::sqrt(float(j) / M)) *
                    std::max(invDist[at(j, k)], invDist[at(j, kPrev)]);
      for (int c = 0; c < 3; ++c) translational[c] += v * (scale * (L[at(j, k)][c] - L[at(j, kPrev)][c]));
    }
  }
  for (int c = 0; c < 3; ++c) {
    rec.rotationalGradient[c] = frame.toWorld(rotational[c] * cellMeasure);
    rec.translationalGradient[c] = frame.toWorld(translational[c]);
    // Huge radiance (a tiny light seen at the horizon) times 1/r can overflow:
    // such a gradient says nothing useful, so the record keeps none.
    if (!isFinite(rec.rotationalGradient[c])) rec.rotationalGradient[c] = Vec3(0.f);
    if (!isFinite(rec.translationalGradient[c])) rec.translationalGradient[c] = Vec3(0.f);
  }
  return rec;
}

}  // namespace lb
