#pragma once
// Diffuse area emitter on any shape: constant radiance on the front side (the
// side of the geometric normal), or on both sides. Spheres are sampled by the
// solid angle they subtend, other shapes uniformly by area.
#include "core/lights/light.h"
#include "core/shape.h"

namespace lb {

class AreaLight final : public Light {
 public:
  AreaLight(const Shape* shape, Color radiance, bool twoSided) : shape_(shape), radiance_(radiance), twoSided_(twoSided) {}

  std::optional<LightSample> sampleLi(const Vec3& ref, float uPick, Vec2 u) const override;
  float pdfLi(const Vec3& ref, const Vec3& wi, const Vec3& pLight, const Vec3& nLight) const override;
  std::optional<LightEmission> sampleLe(float uPick, Vec2 uPos, Vec2 uDir) const override;
  void pdfLe(const Vec3& p, const Vec3& n, const Vec3& dir, float* pdfPos, float* pdfDir) const override;
  Color power() const override { return radiance_ * shape_->area() * Pi * (twoSided_ ? 2.f : 1.f); }
  Color L(const Vec3& n, const Vec3& w) const override {
    return (twoSided_ || glm::dot(n, w) > 0) ? radiance_ : Color(0.f);
  }
  bool isDelta() const override { return false; }

 private:
  const Shape* shape_;
  Color radiance_;
  bool twoSided_;
};

}  // namespace lb
