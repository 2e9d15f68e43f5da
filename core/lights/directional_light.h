#pragma once
// Directional light: parallel light travelling along `direction`, irradiance E
// on a plane perpendicular to it. Emitted rays start on a disc covering the
// scene's bounding sphere.
#include "core/frame.h"
#include "core/lights/light.h"
#include "core/sampling.h"

namespace lb {

class DirectionalLight final : public Light {
 public:
  DirectionalLight(Vec3 direction, Color irradiance) : frame_(glm::normalize(direction)), irradiance_(irradiance) {}

  // An empty scene has zero radius; a unit sphere keeps the emission pdfs finite.
  void preprocess(const Bounds3& b) override { center_ = b.center(), radius_ = b.radius() > 0 ? b.radius() : 1.f; }
  std::optional<LightSample> sampleLi(const Vec3& ref, float, Vec2) const override {
    Vec3 wi = -frame_.n;
    return LightSample{irradiance_, wi, 1.f, ref + wi * (2 * radius_ + glm::length(ref - center_))};
  }
  float pdfLi(const Vec3&, const Vec3&, const Vec3&, const Vec3&) const override { return 0; }
  std::optional<LightEmission> sampleLe(float, Vec2 uPos, Vec2) const override {
    Vec2 d = sampleConcentricDisk(uPos);
    Vec3 origin = center_ - frame_.n * radius_ + radius_ * (d.x * frame_.s + d.y * frame_.t);
    LightEmission e;
    e.ray = {origin, frame_.n, Infinity};
    e.p = e.ray.o;
    e.Le = irradiance_;
    e.pdfPos = 1 / (Pi * radius_ * radius_);
    e.pdfDir = 1;
    return e;
  }
  void pdfLe(const Vec3&, const Vec3&, const Vec3&, float* pdfPos, float* pdfDir) const override {
    *pdfPos = 1 / (Pi * radius_ * radius_), *pdfDir = 0;
  }
  Color power() const override { return irradiance_ * Pi * radius_ * radius_; }
  bool isDelta() const override { return true; }
  bool isInfinite() const override { return true; }

 private:
  Frame frame_;
  Color irradiance_;
  Vec3 center_{0.f};
  float radius_ = 1;
};

}  // namespace lb
