#include "core/lights/area_light.h"
#include "core/sampling.h"

namespace lb {

std::optional<LightSample> AreaLight::sampleLi(const Vec3& ref, float uPick, Vec2 u) const {
  ShapeSample ss;
  float pdf;
  Vec3 d;
  float dist;
  if (shape_->isSphere()) {
    ss = shape_->sampleSolidAngle(ref, u, &pdf);
    d = ss.p - ref;
    dist = glm::length(d);
  } else {
    ss = shape_->sampleArea(uPick, u);
    d = ss.p - ref;
    float dist2 = glm::dot(d, d);
    if (dist2 == 0) return std::nullopt;
    dist = std::sqrt(dist2);
    float cos = absDot(ss.n, d) / dist;
    if (cos == 0) return std::nullopt;
    pdf = ss.pdfArea * dist2 / cos;  // area → solid angle
  }
  if (dist == 0 || pdf == 0 || !std::isfinite(pdf)) return std::nullopt;
  Vec3 wi = d / dist;
  Color Le = L(ss.n, -wi);
  if (isBlack(Le)) return std::nullopt;
  return LightSample{Le, wi, pdf, ss.p, ss.pError, ss.n};
}

float AreaLight::pdfLi(const Vec3& ref, const Vec3& wi, const Vec3& pLight, const Vec3& nLight) const {
  if (shape_->isSphere()) return shape_->solidAnglePdf(ref, pLight, nLight);
  Vec3 d = pLight - ref;
  float dist2 = glm::dot(d, d);
  float cos = absDot(nLight, wi);
  return cos > 0 ? dist2 / (cos * shape_->area()) : 0.f;
}

std::optional<LightEmission> AreaLight::sampleLe(float uPick, Vec2 uPos, Vec2 uDir) const {
  ShapeSample ss = shape_->sampleArea(uPick, uPos);
  Vec3 local;
  float sidePdf = 1;
  Vec3 n = ss.n;
  if (twoSided_) {  // pick a side with probability 1/2, reusing uDir.x
    sidePdf = 0.5f;
    if (uDir.x < 0.5f) uDir.x = std::min(uDir.x * 2, OneMinusEpsilon);
    else uDir.x = std::min((uDir.x - 0.5f) * 2, OneMinusEpsilon), n = -n;
  }
  local = sampleCosineHemisphere(uDir);
  if (local.z == 0) return std::nullopt;
  Vec3 dir = Frame(n).toWorld(local);
  LightEmission e;
  e.ray = {offsetRayOrigin(ss.p, ss.pError, ss.n, dir), dir, Infinity};
  e.p = ss.p;
  e.n = n;  // the emitting side's normal, so cos(n, dir) > 0
  e.pError = ss.pError;
  e.Le = radiance_;
  e.pdfPos = ss.pdfArea;
  e.pdfDir = sidePdf * cosineHemispherePdf(local.z);
  return e;
}

void AreaLight::pdfLe(const Vec3&, const Vec3& n, const Vec3& dir, float* pdfPos, float* pdfDir) const {
  *pdfPos = 1 / shape_->area();
  float cos = glm::dot(n, dir);
  *pdfDir = twoSided_ ? 0.5f * std::abs(cos) * InvPi : cosineHemispherePdf(cos);
}

}  // namespace lb
