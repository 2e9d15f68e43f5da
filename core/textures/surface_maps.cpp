#include "core/textures/surface_maps.h"
#include <cstring>
#include "core/rng.h"

namespace lb {

float opacityOf(const Color& value) { return glm::clamp(luminance(value), 0.f, 1.f); }

namespace {

// The unit tangent along t in the plane normal to n, or any tangent if t has
// no component there.
Vec3 tangentAlong(const Vec3& t, const Vec3& n) {
  Vec3 s = t - n * glm::dot(n, t);
  float len = glm::length(s);
  return len > 1e-12f ? s / len : Frame(n).s;
}

}  // namespace

void applyShadingMaps(const Material& material, SurfaceInteraction& si) {
  const Material::SurfaceMaps& maps = material.surfaceMaps();
  Vec3 n = si.shading.n, nNew = n;
  if (maps.normal) {
    Color c = maps.normal->eval(si.uv);
    Vec3 local = Vec3(2 * c.r - 1, 2 * c.g - 1, 2 * c.b - 1);
    Vec3 s = tangentAlong(si.dpdu, n), t = glm::cross(n, s);
    nNew = s * local.x + t * local.y + n * local.z;
  } else if (maps.bump) {
    Vec2 grad = maps.bumpScale * maps.bump->luminanceGradient(si.uv);
    Vec3 dpdu = si.dpdu + n * (grad.x - glm::dot(n, si.dpdu));
    Vec3 dpdv = si.dpdv + n * (grad.y - glm::dot(n, si.dpdv));
    nNew = glm::cross(dpdu, dpdv);
    if (glm::dot(nNew, n) < 0) nNew = -nNew;
  }
  float len = glm::length(nNew);
  if (!(len > 0) || !std::isfinite(len)) return;  // a degenerate map texel: the surface's own normal
  si.shading = Frame(nNew / len);
}

bool passesThrough(float alpha, const Vec3& o, const Vec3& d, unsigned geometry, unsigned primitive) {
  if (alpha >= 1) return false;
  if (alpha <= 0) return true;
  auto bits = [](float f) {
    uint32_t b;
    std::memcpy(&b, &f, sizeof b);
    return uint64_t(b);
  };
  uint64_t h = hashValues(bits(o.x), bits(o.y), bits(o.z), bits(d.x), bits(d.y), bits(d.z), geometry, primitive);
  float u = float(h >> 40) * 0x1p-24f;  // 24 bits: uniform on [0, 1)
  return u >= alpha;
}

}  // namespace lb
