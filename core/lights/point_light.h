#pragma once
// Isotropic point light of intensity I (W/sr): L arriving at distance r is I/r².
#include "core/lights/light.h"
#include "core/sampling.h"

namespace lb {

class PointLight final : public Light {
 public:
  PointLight(Vec3 position, Color intensity) : position_(position), intensity_(intensity) {}

  std::optional<LightSample> sampleLi(const Vec3& ref, float, Vec2) const override {
    Vec3 d = position_ - ref;
    float dist2 = glm::dot(d, d);
    if (dist2 == 0) return std::nullopt;
    return LightSample{intensity_ / dist2, d / std::sqrt(dist2), 1.f, position_};
  }
  float pdfLi(const Vec3&, const Vec3&, const Vec3&, const Vec3&) const override { return 0; }
  std::optional<LightEmission> sampleLe(float, Vec2, Vec2 uDir) const override {
    LightEmission e;
    e.ray = {position_, sampleUniformSphere(uDir), Infinity};
    e.p = e.ray.o;
    e.Le = intensity_;
    e.pdfPos = 1;
    e.pdfDir = uniformSpherePdf();
    return e;
  }
  void pdfLe(const Vec3&, const Vec3&, const Vec3&, float* pdfPos, float* pdfDir) const override {
    *pdfPos = 0, *pdfDir = uniformSpherePdf();
  }
  Color power() const override { return 4 * Pi * intensity_; }
  bool isDelta() const override { return true; }

 private:
  Vec3 position_;
  Color intensity_;
};

}  // namespace lb
