#pragma once
// Constant environment: radiance Le arriving from every direction. Sampled
// uniformly over the sphere; emitted rays start on a disc covering the scene's
// bounding sphere, facing the sampled direction.
#include "core/frame.h"
#include "core/lights/light.h"
#include "core/sampling.h"

namespace lb {

// An infinite light's emitted ray arriving from direction `towards` (pointing
// at the environment): it starts on the disc of the scene's bounding sphere
// facing that direction, so it crosses the whole scene (pdfPos 1/(π r²)).
inline LightEmission emitFromBoundingDisc(const Vec3& center, float radius, const Vec3& towards, Vec2 uPos) {
  Frame frame(-towards);
  Vec2 d = sampleConcentricDisk(uPos);
  LightEmission e;
  e.ray = {center + towards * radius + radius * (d.x * frame.s + d.y * frame.t), -towards, Infinity};
  e.p = e.ray.o;
  e.pdfPos = 1 / (Pi * radius * radius);
  return e;
}

class EnvironmentLight final : public Light {
 public:
  explicit EnvironmentLight(Color radiance) : radiance_(radiance) {}

  // An empty scene has zero radius; a unit sphere keeps the emission pdfs finite.
  void preprocess(const Bounds3& b) override { center_ = b.center(), radius_ = b.radius() > 0 ? b.radius() : 1.f; }
  std::optional<LightSample> sampleLi(const Vec3& ref, float, Vec2 u) const override {
    Vec3 wi = sampleUniformSphere(u);
    return LightSample{radiance_, wi, uniformSpherePdf(), ref + wi * (2 * radius_ + glm::length(ref - center_))};
  }
  float pdfLi(const Vec3&, const Vec3&, const Vec3&, const Vec3&) const override { return uniformSpherePdf(); }
  std::optional<LightEmission> sampleLe(float, Vec2 uPos, Vec2 uDir) const override {
    Vec3 w = sampleUniformSphere(uDir);  // direction towards the environment
    LightEmission e = emitFromBoundingDisc(center_, radius_, w, uPos);
    e.Le = radiance_;
    e.pdfDir = uniformSpherePdf();
    return e;
  }
  void pdfLe(const Vec3&, const Vec3&, const Vec3&, float* pdfPos, float* pdfDir) const override {
    *pdfPos = 1 / (Pi * radius_ * radius_), *pdfDir = uniformSpherePdf();
  }
  Color power() const override { return radiance_ * 4.f * Pi * Pi * radius_ * radius_; }
  Color Le(const Vec3&) const override { return radiance_; }
  bool isDelta() const override { return false; }
  bool isInfinite() const override { return true; }

 private:
  Color radiance_;
  Vec3 center_{0.f};
  float radius_ = 1;
};

}  // namespace lb
