#pragma once
// Spot light: intensity I inside a cone, with a smooth falloff between the
// falloff-start angle and the cone's edge (pbrt-v4 §12.2.1).
#include "core/frame.h"
#include "core/lights/light.h"
#include "core/sampling.h"

namespace lb {

class SpotLight final : public Light {
 public:
  SpotLight(Vec3 position, Vec3 direction, Color intensity, float coneDegrees, float falloffStartDegrees)
      : position_(position), frame_(glm::normalize(direction)), intensity_(intensity),
        cosTotal_(std::cos(glm::radians(coneDegrees))), cosStart_(std::max(std::cos(glm::radians(falloffStartDegrees)), cosTotal_)) {}

  Color I(const Vec3& w) const {
    float c = glm::dot(w, frame_.n);
    if (c <= cosTotal_) return Color(0.f);
    if (c >= cosStart_) return intensity_;
    float t = (c - cosTotal_) / (cosStart_ - cosTotal_);
    return intensity_ * (t * t * (3 - 2 * t));  // smoothstep
  }
  std::optional<LightSample> sampleLi(const Vec3& ref, float, Vec2) const override {
    Vec3 d = position_ - ref;
    float dist2 = glm::dot(d, d);
    if (dist2 == 0) return std::nullopt;
    Vec3 wi = d / std::sqrt(dist2);
    Color L = I(-wi) / dist2;
    if (isBlack(L)) return std::nullopt;
    return LightSample{L, wi, 1.f, position_};
  }
  float pdfLi(const Vec3&, const Vec3&, const Vec3&, const Vec3&) const override { return 0; }
  std::optional<LightEmission> sampleLe(float, Vec2, Vec2 uDir) const override {
    LightEmission e;
    Vec3 w = frame_.toWorld(sampleUniformCone(uDir, cosTotal_));
    e.ray = {position_, w, Infinity};
    e.p = e.ray.o;
    e.Le = I(w);
    e.pdfPos = 1;
    e.pdfDir = uniformConePdf(cosTotal_);
    return e;
  }
  void pdfLe(const Vec3&, const Vec3&, const Vec3& dir, float* pdfPos, float* pdfDir) const override {
    *pdfPos = 0;
    *pdfDir = glm::dot(dir, frame_.n) > cosTotal_ ? uniformConePdf(cosTotal_) : 0.f;
  }
  Color power() const override {
    return intensity_ * 2.f * Pi * ((1 - cosStart_) + (cosStart_ - cosTotal_) / 2);
  }
  bool isDelta() const override { return true; }

 private:
  Vec3 position_;
  Frame frame_;
  Color intensity_;
  float cosTotal_, cosStart_;
};

}  // namespace lb
