#pragma once
// Pixel reconstruction filters, by filter importance sampling (Ernst et al.
// 2006; pbrt-v4 §8.8). Pixel (x, y) estimates
//   I(x, y) = ∫ f̂(p − c) L(p) dp,   c = (x + ½, y + ½),   f̂ = f / ∫f,
// the image convolved with the normalised filter f̂. A camera sample draws
// the offset p − c with density q ∝ |f| and carries the weight f̂ / q: 1 for
// a positive filter sampled exactly (box, tent), ±∫|f|/∫f for one with
// negative lobes. So every sample still belongs to one pixel, and per-pixel
// variance, adaptive sampling, crops, chunks and thread-count independence
// are unchanged.
//
// A splat (light tracing, BDPT's t = 1, VCM) lands at a raster point p with a
// value V that estimates L(p) per unit of image area; pixel (x, y) gets
// f̂(p − c)·V, which estimates the same ∫ f̂(p − c) L(p) dp. Both strategies
// therefore estimate the same pixel value, and BDPT's MIS weights, computed
// from the camera's nominal densities (uniform over the image plane, and over
// the margin of radius − ½ pixel around it that filtered pixels reach), sum
// to one for every path as before: the filter changes what a pixel measures,
// not which paths exist.
//
// Filters are separable, f(dx, dy) = f₁(dx)·f₁(dy), as in pbrt-v4 and Mitsuba 3:
//   box       f₁ = 1 on [−r, r]                         (r = ½: one pixel; the default)
//   tent      f₁ = r − |x|                              (Mitsuba "tent", pbrt "triangle")
//   gaussian  f₁ = max(0, e^(−x²/2σ²) − e^(−r²/2σ²))
//   mitchell  Mitchell & Netravali 1988 with B, C, on x·2/r
//   lanczos   sinc(x)·sinc(x/τ) for |x| < r  (Mitsuba: τ = r = lobes)
#include <string>
#include <vector>
#include "core/math.h"

namespace lb {

class PixelFilter {
 public:
  enum class Type { Box, Tent, Gaussian, Mitchell, Lanczos };
  static constexpr int MaxRadius = 16;  // pixels; a radius outside (0, MaxRadius] throws std::invalid_argument
  PixelFilter() = default;  // the one-pixel box
  // `a`, `b`: gaussian σ; mitchell B, C; lanczos τ (b unused). The caller
  // checks the ranges (scene_loader.cpp states them).
  PixelFilter(Type type, float radius, float a = 0, float b = 0);
  static const std::vector<std::string>& names();  // "box", "tent", … in Type's order
  static Type typeNamed(const std::string& name);   // one of names()

  Type type() const { return type_; }
  float radius() const { return radius_; }
  bool isPixelBox() const { return type_ == Type::Box && radius_ == 0.5f; }
  // How far past the image's edge (in pixels) a filtered pixel looks: r − ½.
  float margin() const { return radius_ > 0.5f ? radius_ - 0.5f : 0.f; }

  // f̂ at an offset from a pixel's centre (0 outside the radius), and its
  // one-dimensional factor f₁ / ∫f₁ (f̂ is the product of two).
  float evaluate(Vec2 offset) const { return normalised1D(offset.x) * normalised1D(offset.y); }
  float normalised1D(float x) const { return evaluate1D(x) / integral1_; }
  // The unnormalised f₁, and ∫ f₁.
  float evaluate1D(float x) const;
  float integral1D() const { return integral1_; }

  struct Sample {
    Vec2 offset;  // from the pixel's centre
    float weight; // f̂(offset) / pdf(offset)
  };
  Sample sample(Vec2 u) const;
  // The density sample() draws offsets with.
  float pdf(Vec2 offset) const { return pdf1D(offset.x) * pdf1D(offset.y); }

 private:
  float sample1D(float u, float* weight) const;
  float pdf1D(float x) const;

  Type type_ = Type::Box;
  float radius_ = 0.5f, a_ = 0, b_ = 0;
  float integral1_ = 1;  // ∫ f₁
  // Filters without an exact inverse: |f₁| tabulated on [−r, r] in bins,
  // sampled piecewise constant (density proportional to each bin's ∫|f₁|).
  std::vector<float> binCdf_, binPdf_;
};

}  // namespace lb
