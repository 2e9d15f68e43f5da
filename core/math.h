#pragma once
// Shared numeric vocabulary: GLM vector types, constants, and the floating-point
// error bound gamma(n) of pbrt-v4 (Higham's (1+eps)^n bound) used for ray offsets.
#include <glm/glm.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace lb {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using Vec3d = glm::dvec3;
using Mat3 = glm::mat3;
using Mat4 = glm::mat4;
using Color = glm::vec3;  // linear RGB radiance / reflectance

constexpr float Pi = 3.14159265358979323846f;
constexpr float InvPi = 1.f / Pi;
constexpr float Inv2Pi = 1.f / (2.f * Pi);
constexpr float Inv4Pi = 1.f / (4.f * Pi);
constexpr float Infinity = std::numeric_limits<float>::infinity();
constexpr float OneMinusEpsilon = 0x1.fffffep-1f;
constexpr float MachineEpsilon = std::numeric_limits<float>::epsilon() * 0.5f;

// Bound on the relative error of n chained float operations (pbrt-v4 §6.8.1).
constexpr float gamma(int n) { return (n * MachineEpsilon) / (1 - n * MachineEpsilon); }

inline float sqr(float x) { return x * x; }
inline float safeSqrt(float x) { return std::sqrt(std::max(0.f, x)); }
inline float luminance(const Color& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }
inline float maxComponent(const Color& c) { return std::max(c.r, std::max(c.g, c.b)); }
inline bool isBlack(const Color& c) { return c.r == 0.f && c.g == 0.f && c.b == 0.f; }
inline bool isFinite(const Color& c) {
  return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b);
}
inline float absDot(const Vec3& a, const Vec3& b) { return std::abs(glm::dot(a, b)); }
// The neighbouring float above (below) v, as std::nextafter(v, ±∞) but inline
// (pbrt-v4 §6.8.2): every spawned ray calls it up to three times per end, and
// libm's nextafterf was a call per axis in the path tracer's profile (issue 33).
// On the bits alone, so flush-to-zero (which the renderers enable) cannot
// change it: −0 steps to the smallest denormal, +∞ and NaN stay.
inline float nextFloatUp(float v) {
  uint32_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  if ((bits & 0x7fffffffu) >= 0x7f800000u && bits != 0xff800000u) return v;  // NaN, +∞
  if (bits == 0x80000000u) bits = 0;                                           // −0 → +0
  bits = (bits & 0x80000000u) ? bits - 1 : bits + 1;  // negative: towards zero
  std::memcpy(&v, &bits, sizeof bits);
  return v;
}
inline float nextFloatDown(float v) { return -nextFloatUp(-v); }

// Axis-aligned bounds, used for the scene's bounding sphere (infinite lights).
struct Bounds3 {
  Vec3 lo{Infinity}, hi{-Infinity};
  void extend(const Vec3& p) { lo = glm::min(lo, p), hi = glm::max(hi, p); }
  void extend(const Bounds3& b) { lo = glm::min(lo, b.lo), hi = glm::max(hi, b.hi); }
  bool empty() const { return lo.x > hi.x; }
  Vec3 center() const { return 0.5f * (lo + hi); }
  float radius() const { return 0.5f * glm::length(hi - lo); }
};

}  // namespace lb
