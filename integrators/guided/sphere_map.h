#pragma once
// The sphere of directions as the unit square, by the cylindrical (Lambert)
// equal-area map both guiding methods use (Müller et al. 2017, §3.3):
//   c.x = (cos θ + 1) / 2,  c.y = φ / 2π,   with cos θ = ω.z, φ = atan2(ω.y, ω.x),
// so a region of the square of area a covers solid angle 4π·a, and a density
// over the square becomes one over directions by dividing by 4π.
#include <cmath>
#include "core/math.h"

namespace lb::guiding {

constexpr float FourPi = 4 * Pi;

inline Vec2 squareFromDirection(const Vec3& w) {
  float phi = std::atan2(w.y, w.x);
  if (phi < 0) phi += 2 * Pi;
  Vec2 c{0.5f * (std::clamp(w.z, -1.f, 1.f) + 1), phi / (2 * Pi)};
  return glm::min(c, Vec2(OneMinusEpsilon));
}

inline Vec3 directionFromSquare(Vec2 c) {
  float z = 2 * c.x - 1, phi = 2 * Pi * c.y;
  float r = std::sqrt(std::max(0.f, 1 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace lb::guiding
