#pragma once
// Light interface. Every light samples in both directions:
//  * towards itself from a reference point (next-event estimation), with the
//    solid-angle pdf at the reference point, and pdfLi for a given direction;
//  * an emitted ray (light tracing, photon mapping), with separate position and
//    direction pdfs, and pdfLe for a given emitted ray.
// Delta lights (point, spot, directional) report pdf = 1 for sampleLi and cannot
// be hit by rays. Infinite lights (directional, environment) need the scene's
// bounding sphere, given in preprocess().
#include <optional>
#include "core/interaction.h"

namespace lb {

struct LightSample {
  Color L{0.f};   // radiance (or, for delta lights, intensity / r²) arriving at ref
  Vec3 wi;        // unit direction from ref towards the light
  float pdf = 0;  // solid angle at ref (1 for delta lights)
  Vec3 p, pError{0.f}, n{0.f};  // the sampled point (far away for infinite lights)
};

struct LightEmission {
  Ray ray;
  Vec3 p{0.f};     // the sampled point itself (ray.o is offset off the surface)
  Vec3 n{0.f};     // normal of the emitting side at the origin (0 for point-like sources)
  Vec3 pError{0.f};
  Color Le{0.f};   // emitted radiance (or intensity) along the ray
  float pdfPos = 0, pdfDir = 0;
};

class Light {
 public:
  virtual ~Light() = default;
  virtual std::optional<LightSample> sampleLi(const Vec3& ref, float uPick, Vec2 u) const = 0;
  // For lights that can be hit: the pdf sampleLi would give for the point
  // (pLight, nLight) seen from ref along wi. 0 for delta lights.
  virtual float pdfLi(const Vec3& ref, const Vec3& wi, const Vec3& pLight, const Vec3& nLight) const = 0;
  // Next-event estimation's density made for multiple importance sampling
  // with an estimator that also samples the BSDF (MIS compensation, Karlík,
  // Šik, Vévoda, Skřivan & Křivánek 2019): it may be zero where the other
  // strategy does better (an environment map below its mean), so it is only
  // for an estimator whose BSDF sampling reaches every direction and whose
  // weights use these same densities. Lights without one use their own.
  virtual std::optional<LightSample> sampleLiCompensated(const Vec3& ref, float uPick, Vec2 u) const {
    return sampleLi(ref, uPick, u);
  }
  virtual float pdfLiCompensated(const Vec3& ref, const Vec3& wi, const Vec3& pLight, const Vec3& nLight) const {
    return pdfLi(ref, wi, pLight, nLight);
  }
  virtual std::optional<LightEmission> sampleLe(float uPick, Vec2 uPos, Vec2 uDir) const = 0;
  virtual void pdfLe(const Vec3& p, const Vec3& n, const Vec3& dir, float* pdfPos, float* pdfDir) const = 0;
  virtual Color power() const = 0;
  // Area lights: radiance leaving a surface point with normal n in direction w.
  virtual Color L(const Vec3& /*n*/, const Vec3& /*w*/) const { return Color(0.f); }
  // Infinite lights: radiance arriving along a ray that escapes with direction d.
  virtual Color Le(const Vec3& /*d*/) const { return Color(0.f); }
  virtual void preprocess(const Bounds3& /*sceneBounds*/) {}

  virtual bool isDelta() const = 0;
  virtual bool isInfinite() const { return false; }
  int index = -1;  // position in the scene's light list
};

}  // namespace lb
