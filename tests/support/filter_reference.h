#pragma once
// The pixel filters' one-dimensional profiles written again from their
// definitions, for the tests to check core/filter.cpp against (not shared
// with it): pbrt-v4 §8.8.1–8.8.5 and Mitsuba 3's rfilter documentation.
//   box       1
//   tent      r − |x|
//   gaussian  e^(−x²/2σ²) − e^(−r²/2σ²), clamped at 0
//   mitchell  Mitchell & Netravali 1988, Eq. 8, at t = 2|x|/r
//   lanczos   sinc(x)·sinc(x/τ)
// all zero for |x| > r. Integrals by a composite Simpson rule in double.
#include <cmath>
#include <string>
#include "core/filter.h"

namespace lb::test {

struct FilterCase {
  std::string name;
  PixelFilter::Type type;
  double radius, a = 0, b = 0;  // gaussian σ; mitchell B, C; lanczos τ
  PixelFilter make() const { return PixelFilter(type, float(radius), float(a), float(b)); }
};

inline double filterReference1D(const FilterCase& c, double x) {
  x = std::abs(x);
  if (x > c.radius) return 0;
  const double pi = 3.14159265358979323846;
  auto sinc = [&](double v) { return v == 0 ? 1.0 : std::sin(pi * v) / (pi * v); };
  switch (c.type) {
    case PixelFilter::Type::Box: return 1;
    case PixelFilter::Type::Tent: return c.radius - x;
    case PixelFilter::Type::Gaussian:
      return std::max(0.0, std::exp(-x * x / (2 * c.a * c.a)) - std::exp(-c.radius * c.radius / (2 * c.a * c.a)));
    case PixelFilter::Type::Mitchell: {
      double t = 2 * x / c.radius, B = c.a, C = c.b;
      if (t < 1) return ((12 - 9 * B - 6 * C) * t * t * t + (-18 + 12 * B + 6 * C) * t * t + (6 - 2 * B)) / 6;
      if (t < 2) return ((-B - 6 * C) * t * t * t + (6 * B + 30 * C) * t * t + (-12 * B - 48 * C) * t + (8 * B + 24 * C)) / 6;
      return 0;
    }
    case PixelFilter::Type::Lanczos: return sinc(x) * sinc(x / c.a);
  }
  return 0;
}

// ∫ from lo to hi of the profile, or of its absolute value (Simpson, 2·n panels).
inline double filterReferenceIntegral(const FilterCase& c, double lo, double hi, int n = 2000, bool absolute = false) {
  lo = std::max(lo, -c.radius), hi = std::min(hi, c.radius);
  if (!(hi > lo)) return 0;
  auto f = [&](double x) { return absolute ? std::abs(filterReference1D(c, x)) : filterReference1D(c, x); };
  double h = (hi - lo) / (2 * n), sum = f(lo) + f(hi);
  for (int i = 1; i < 2 * n; ++i) sum += (i % 2 ? 4 : 2) * f(lo + i * h);
  return sum * h / 3;
}

// The normalised profile's integral up to t: a pixel's value beside a step
// edge t pixels from its centre (L = 1 on the side of −∞).
inline double filterReferenceCdf(const FilterCase& c, double t) {
  return filterReferenceIntegral(c, -c.radius, t) / filterReferenceIntegral(c, -c.radius, c.radius);
}

inline std::vector<FilterCase> filterCases() {
  using T = PixelFilter::Type;
  return {{"box", T::Box, 0.5},           {"wide_box", T::Box, 1.5},
          {"tent", T::Tent, 1},           {"wide_tent", T::Tent, 2},
          {"gaussian", T::Gaussian, 2, 0.5}, {"narrow_gaussian", T::Gaussian, 1.5, 0.3},
          {"mitchell", T::Mitchell, 2, 1.0 / 3, 1.0 / 3}, {"catmull_rom", T::Mitchell, 2, 0, 0.5},
          {"lanczos", T::Lanczos, 3, 3},  {"lanczos2", T::Lanczos, 2, 2}};
}

}  // namespace lb::test
