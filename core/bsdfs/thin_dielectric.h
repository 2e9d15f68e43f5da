#pragma once
// An infinitely thin dielectric slab (Mitsuba 3 `thindielectric`, pbrt-v4
// ThinDielectricBxDF): light reflects off, or passes straight through, a sheet
// of index `ior` relative to the outside. Summing the inter-reflections inside
// the slab with single-interface Fresnel R and T = 1 - R gives
//   R' = R + T² R / (1 - R²),   T' = 1 - R'.
// Both lobes are delta. Transmission exits parallel to the incident ray, so it
// crosses no net IOR: eta = 1 and no 1/η² in either transport mode.
#include "core/bsdfs/fresnel.h"
#include "core/bsdfs/material.h"

namespace lb {

class ThinDielectric final : public Material {
 public:
  explicit ThinDielectric(float ior) : ior_(ior) {}

  // R' at |cos θ| (symmetric: the slab looks the same from either side).
  float reflectance(float cosTheta) const {
    float R = fresnelDielectric(std::abs(cosTheta), ior_), T = 1 - R;
    if (R < 1) R += T * T * R / (1 - R * R);
    return R;
  }

  BSDFEval eval(const Vec3&, const Vec3&, TransportMode) const override { return {}; }
  std::optional<BSDFSample> sample(const Vec3& wo, float uLobe, Vec2, TransportMode) const override {
    if (wo.z == 0) return std::nullopt;
    float R = reflectance(wo.z), T = 1 - R;
    // Both lobes keep |cos θ|, so the reverse probability equals the forward one.
    if (uLobe < R) {
      Vec3 wi(-wo.x, -wo.y, wo.z);
      return BSDFSample{wi, Color(R / absCosTheta(wi)), R, R, BSDFReflection | BSDFSpecular};
    }
    Vec3 wi = -wo;
    return BSDFSample{wi, Color(T / absCosTheta(wi)), T, T, BSDFTransmission | BSDFSpecular, 1.f};
  }
  float pdf(const Vec3&, const Vec3&) const override { return 0; }
  uint32_t flags() const override { return BSDFReflection | BSDFTransmission | BSDFSpecular; }

 private:
  float ior_;
};

}  // namespace lb
