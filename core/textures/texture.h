#pragma once
// Textures: a colour that varies over a surface's (u, v). A material may carry
// one, and the BSDF wrapper (core/bsdfs/bsdf.h) multiplies the material's f by
// its value at the hit's uv — exact for every material whose f is linear in the
// textured quantity (a diffuse albedo, a conductor's tint), which is what
// lightbench textures. The BSDF interface itself does not change.
//
// Conventions (Mitsuba's, so imported scenes map alike): (u, v) = (0, 0) is
// the image's top-left corner, u grows to the right and v downwards; the
// texture repeats outside [0, 1)². OBJ files, whose vt has v = 0 at the
// bottom, are flipped on load (core/mesh_io.cpp), as Mitsuba does. A 2 × 3 affine `uv_transform` [a b c; d e f] maps
// the surface's uv to the texture's: u' = a u + b v + c, v' = d u + e v + f.
#include <algorithm>
#include <array>
#include <memory>
#include <string>
#include "core/image.h"
#include "core/math.h"

namespace lb {

class Params;

class Texture {
 public:
  explicit Texture(const std::array<float, 6>& uvTransform) : m_(uvTransform) {}
  virtual ~Texture() = default;
  Color eval(Vec2 uv) const { return lookup(Vec2(m_[0] * uv.x + m_[1] * uv.y + m_[2], m_[3] * uv.x + m_[4] * uv.y + m_[5])); }
  // The largest value any uv can return (energy conservation is checked on it).
  virtual Color maxValue() const = 0;
  // The average over one period: what an approximation by a constant uses.
  virtual Color mean() const = 0;
  // The gradient of the value's luminance with respect to the surface's
  // (u, v), by central differences half a texel wide (bump maps). Over a
  // bilinear texel this is the exact derivative; across a texel edge it is
  // the mean of the two slopes.
  Vec2 luminanceGradient(Vec2 uv) const;

 protected:
  virtual Color lookup(Vec2 uv) const = 0;
  // A texel's width in the texture's own (u, v); images override.
  virtual float texelSize() const { return 1e-3f; }

 private:
  std::array<float, 6> m_;
};

// An image, bilinearly filtered (or nearest), repeating. Texel (x, y) has its
// centre at u = (x + ½)/W, v = (y + ½)/H (row 0 is the image's top).
class ImageTexture final : public Texture {
 public:
  ImageTexture(Image image, bool bilinear, const std::array<float, 6>& uvTransform);
  Color maxValue() const override { return max_; }
  Color mean() const override { return mean_; }

 private:
  Color lookup(Vec2 uv) const override;
  float texelSize() const override { return 1.f / float(std::max(image_.width, image_.height)); }
  Color texel(int x, int y) const;
  Image image_;
  bool bilinear_;
  Color max_{0.f}, mean_{0.f};
};

// Two colours alternating on a 2 × 2 grid per unit square of uv (Mitsuba's
// checkerboard): color0 where the cells' parities agree, else color1.
class CheckerboardTexture final : public Texture {
 public:
  CheckerboardTexture(Color color0, Color color1, const std::array<float, 6>& uvTransform)
      : Texture(uvTransform), c0_(color0), c1_(color1) {}
  Color maxValue() const override { return glm::max(c0_, c1_); }
  Color mean() const override { return (c0_ + c1_) * 0.5f; }

 private:
  Color lookup(Vec2 uv) const override;
  Color c0_, c1_;
};

// `texture: {type: image, file, srgb, filter} | {type: checkerboard, color0, color1}`,
// both with `uv_transform`; files relative to `folder` (PNG or EXR).
std::shared_ptr<const Texture> makeTexture(Params& p, const std::string& folder);

}  // namespace lb
