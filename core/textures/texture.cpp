#include "core/textures/texture.h"
#include "core/image_input.h"
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <utility>
#include "core/params.h"

namespace lb {

namespace {
// Repeat: the texel index modulo the size, also for negative coordinates.
int wrap(int i, int n) { return ((i % n) + n) % n; }
}  // namespace

ImageTexture::ImageTexture(Image image, bool bilinear, const std::array<float, 6>& uvTransform)
    : Texture(uvTransform), image_(std::move(image)), bilinear_(bilinear) {
  for (const Color& c : image_.pixels) {
    max_ = glm::max(max_, c);
    mean_ += c;
  }
  if (!image_.pixels.empty()) mean_ /= float(image_.pixels.size());
}

Color ImageTexture::texel(int x, int y) const { return image_.at(wrap(x, image_.width), wrap(y, image_.height)); }

Color ImageTexture::lookup(Vec2 uv) const {
  // Continuous texel coordinates, row 0 at the top (v = 0).
  float x = uv.x * image_.width, y = uv.y * image_.height;
  if (!std::isfinite(x) || !std::isfinite(y)) return Color(0.f);
  // Keep the coordinates small before flooring (a uv of 1e30 repeats anyway).
  x = std::fmod(x, float(image_.width));
  y = std::fmod(y, float(image_.height));
  if (!bilinear_) return texel(int(std::floor(x)), int(std::floor(y)));
  x -= 0.5f;
  y -= 0.5f;
  int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  float fx = x - x0, fy = y - y0;
  return (1 - fx) * (1 - fy) * texel(x0, y0) + fx * (1 - fy) * texel(x0 + 1, y0) +
         (1 - fx) * fy * texel(x0, y0 + 1) + fx * fy * texel(x0 + 1, y0 + 1);
}

Vec2 Texture::luminanceGradient(Vec2 uv) const {
  // Half a texel in texture space, mapped back through the uv transform's
  // largest scale so a magnified texture is not differenced across texels.
  float scale = std::max({std::abs(m_[0]), std::abs(m_[1]), std::abs(m_[3]), std::abs(m_[4]), 1e-6f});
  float h = 0.5f * texelSize() / scale;
  float du = luminance(eval(uv + Vec2(h, 0))) - luminance(eval(uv - Vec2(h, 0)));
  float dv = luminance(eval(uv + Vec2(0, h))) - luminance(eval(uv - Vec2(0, h)));
  return Vec2(du, dv) / (2 * h);
}

Color CheckerboardTexture::lookup(Vec2 uv) const {
  auto cell = [](float t) { return t - std::floor(t) >= 0.5f; };
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return c1_;
  return cell(uv.x) == cell(uv.y) ? c0_ : c1_;
}

std::shared_ptr<const Texture> makeTexture(Params& p, const std::string& folder) {
  if (!p.has("type")) p.fail("type", "is required (image or checkerboard)");
  std::string type = p.getChoice("type", "", {"image", "checkerboard"});
  std::array<float, 6> m = {1, 0, 0, 0, 1, 0};
  if (p.has("uv_transform")) {
    // [a, b, c, d, e, f]: u' = a u + b v + c, v' = d u + e v + f.
    std::vector<float> v = p.getFloatList("uv_transform", 6);
    std::copy(v.begin(), v.end(), m.begin());
  }
  std::shared_ptr<const Texture> t;
  if (type == "image") {
    std::string file = p.requireString("file");
    bool srgb = p.getBool("srgb", true);
    bool bilinear = p.getChoice("filter", "bilinear", {"bilinear", "nearest"}) == "bilinear";
    std::filesystem::path full = std::filesystem::path(folder) / file;
    if (!isReadableImagePath(full.string()))
      p.fail("file", "'" + file + "': lightbench reads PNG, JPEG, TGA, BMP, TIFF, HDR, PFM and EXR textures");
    std::error_code ec;
    if (!std::filesystem::is_regular_file(full, ec)) p.fail("file", "'" + full.string() + "' is not a readable file");
    Image image;
    try {
      // Float formats hold linear values already; `srgb` applies to integer ones.
      image = readImageFile(full.string(), srgb).rgb;
    } catch (const std::runtime_error& e) {
      p.fail("file", e.what());
    }
    for (const Color& c : image.pixels)
      if (!std::isfinite(c.r) || !std::isfinite(c.g) || !std::isfinite(c.b) || glm::any(glm::lessThan(c, Color(0.f))))
        p.fail("file", "'" + file + "' has a negative, NaN or infinite texel");
    t = std::make_shared<ImageTexture>(std::move(image), bilinear, m);
  } else {
    Color c0 = p.getColor("color0", Color(0.4f)), c1 = p.getColor("color1", Color(0.2f));
    // A texture scales a reflectance (an albedo, a tint), so its values are
    // held to an image texel's rule above: color1: -1 gave negative pixels
    // while albedo: -1 was refused (issue 34). The upper bound is the
    // material's (material_factory.cpp: value × albedo <= 1).
    for (const auto& [key, c] : {std::pair{"color0", c0}, std::pair{"color1", c1}})
      if (!std::isfinite(c.r + c.g + c.b) || glm::any(glm::lessThan(c, Color(0.f))))
        p.fail(key, "must not be negative (a texture scales a reflectance)");
    t = std::make_shared<CheckerboardTexture>(c0, c1, m);
  }
  p.checkUnused();
  return t;
}

}  // namespace lb
