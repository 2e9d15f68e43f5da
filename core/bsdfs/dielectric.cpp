#include "core/bsdfs/dielectric.h"

namespace lb {

std::optional<BSDFSample> SmoothDielectric::sample(const Vec3& wo, float uLobe, Vec2, TransportMode mode) const {
  if (wo.z == 0) return std::nullopt;
  float R = fresnelDielectric(cosTheta(wo), eta_), T = 1 - R;
  if (uLobe < R) {
    Vec3 wi(-wo.x, -wo.y, wo.z);
    return BSDFSample{wi, Color(R / absCosTheta(wi)), R, R, BSDFReflection | BSDFSpecular};
  }
  Vec3 wi;
  float etap;
  if (!refract(wo, Vec3(0, 0, 1), eta_, &etap, &wi) || wi.z == 0) return std::nullopt;
  float ft = T / absCosTheta(wi);
  if (mode == TransportMode::Radiance) ft /= etap * etap;  // radiance compresses into the denser medium
  // Reverse: from wi the same interface has the same Fresnel transmittance.
  return BSDFSample{wi, Color(ft), T, T, BSDFTransmission | BSDFSpecular, etap};
}

bool RoughDielectric::halfVector(const Vec3& wo, const Vec3& wi, Vec3* wm, float* etap) const {
  float cosO = cosTheta(wo), cosI = cosTheta(wi);
  if (cosO == 0 || cosI == 0) return false;
  bool reflect = cosO * cosI > 0;
  *etap = reflect ? 1.f : (cosO > 0 ? eta_ : 1 / eta_);
  Vec3 h = wi * *etap + wo;
  if (glm::dot(h, h) == 0) return false;
  h = glm::normalize(h);
  if (h.z < 0) h = -h;
  if (glm::dot(h, wi) * cosI < 0 || glm::dot(h, wo) * cosO < 0) return false;
  *wm = h;
  return true;
}

BSDFEval RoughDielectric::eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
  Vec3 wm;
  float etap;
  if (!halfVector(wo, wi, &wm, &etap)) return {};
  float F = fresnelDielectric(glm::dot(wo, wm), eta_);
  float cosO = cosTheta(wo), cosI = cosTheta(wi);
  float f;
  if (cosO * cosI > 0) {
    f = mf_.D(wm) * mf_.G(wo, wi) * F / std::abs(4 * cosI * cosO);
  } else {
    float denom = sqr(glm::dot(wi, wm) + glm::dot(wo, wm) / etap) * cosI * cosO;
    f = mf_.D(wm) * (1 - F) * mf_.G(wo, wi) * std::abs(glm::dot(wi, wm) * glm::dot(wo, wm) / denom);
    if (mode == TransportMode::Radiance) f /= etap * etap;
  }
  return {Color(f), pdf(wo, wi), pdf(wi, wo)};
}

float RoughDielectric::pdf(const Vec3& wo, const Vec3& wi) const {
  Vec3 wm;
  float etap;
  if (!halfVector(wo, wi, &wm, &etap)) return 0;
  float R = fresnelDielectric(glm::dot(wo, wm), eta_), T = 1 - R;
  return lobePdf(wo, wi) * (cosTheta(wo) * cosTheta(wi) > 0 ? R : T);
}

float RoughDielectric::lobePdf(const Vec3& wo, const Vec3& wi) const {
  Vec3 wm;
  float etap;
  if (!halfVector(wo, wi, &wm, &etap)) return 0;
  // The normal's density is symmetric in the sign of wo (sampling from below
  // mirrors the problem, pbrt-v4 §9.6.4).
  float pdfWm = mf_.pdfNormal(wo, wm);
  if (cosTheta(wo) * cosTheta(wi) > 0) return pdfWm / (4 * absDot(wo, wm));
  float denom = sqr(glm::dot(wi, wm) + glm::dot(wo, wm) / etap);
  return pdfWm * absDot(wi, wm) / denom;
}

std::optional<BSDFSample> RoughDielectric::sample(const Vec3& wo, float uLobe, Vec2 u, TransportMode mode) const {
  if (wo.z == 0) return std::nullopt;
  Vec3 woUp = wo.z < 0 ? -wo : wo;
  Vec3 wm = mf_.sampleNormal(woUp, u);  // facing +z
  if (glm::dot(woUp, wm) <= 0) return std::nullopt;  // a back-facing normal (Beckmann samples all of D)
  float R = fresnelDielectric(glm::dot(wo, wm), eta_);
  Vec3 wi;
  uint32_t lobe;
  float etap = 1;
  if (uLobe < R) {
    wi = reflect(wo, wm);
    if (!sameHemisphere(wo, wi)) return std::nullopt;
    lobe = BSDFReflection | BSDFGlossy;
  } else {
    if (!refract(wo, wm, eta_, &etap, &wi) || sameHemisphere(wo, wi) || wi.z == 0) return std::nullopt;
    lobe = BSDFTransmission | BSDFGlossy;
  }
  BSDFEval e = eval(wo, wi, mode);
  if (e.pdf == 0) return std::nullopt;
  return BSDFSample{wi, e.f, e.pdf, e.pdfRev, lobe, etap};
}

std::unique_ptr<Material> SmoothDielectric::mollified(float alpha) const {
  // An index-matched interface bends nothing, so there is nothing to
  // mollify; and the rough model cannot represent it (its half-vector
  // wi + wo vanishes for straight transmission: the twin would be black),
  // as the material factory says too.
  if (eta_ == 1.f) return nullptr;
  auto twin = std::make_unique<RoughDielectric>(eta_, alpha);
  shareSurfaceWith(*twin);
  return twin;
}

}  // namespace lb
