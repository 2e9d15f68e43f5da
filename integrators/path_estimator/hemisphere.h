#pragma once
// The path tracer's non-BSDF direction strategies for the classic comparison
// (uniform and cosine-weighted hemisphere sampling), with their pdfs. For
// transmissive materials the side is chosen with probability 1/2, so both
// hemispheres are covered.
#include "core/bsdfs/bsdf.h"
#include "core/sampling.h"

namespace lb {

enum class DirectionSampling { Bsdf, Cosine, Uniform };

struct DirectionChoice {
  Vec3 wi;
  float pdf;
};

inline DirectionChoice sampleHemisphere(DirectionSampling strategy, const BSDF& bsdf, const Vec3& woWorld, float uSide,
                                        Vec2 u) {
  Vec3 local = strategy == DirectionSampling::Cosine ? sampleCosineHemisphere(u) : sampleUniformHemisphere(u);
  float pdf = strategy == DirectionSampling::Cosine ? cosineHemispherePdf(local.z) : uniformHemispherePdf();
  bool below = glm::dot(woWorld, bsdf.shadingNormal()) < 0;
  if (bsdf.material().hasTransmission()) {
    pdf *= 0.5f;
    if (uSide < 0.5f) below = !below;
  }
  if (below) local.z = -local.z;
  return {bsdf.frame().toWorld(local), pdf};
}

inline float hemispherePdf(DirectionSampling strategy, const BSDF& bsdf, const Vec3& woWorld, const Vec3& wiWorld) {
  float cosWi = glm::dot(wiWorld, bsdf.shadingNormal());
  bool sameSide = cosWi * glm::dot(woWorld, bsdf.shadingNormal()) > 0;
  bool transmissive = bsdf.material().hasTransmission();
  if (!sameSide && !transmissive) return 0;
  float pdf = strategy == DirectionSampling::Cosine ? std::abs(cosWi) * InvPi : uniformHemispherePdf();
  return transmissive ? 0.5f * pdf : pdf;
}

}  // namespace lb
