#include "core/shape.h"

namespace lb {

Shape Shape::mesh(TriangleMesh mesh) {
  Shape s;
  std::vector<float> areas;
  areas.reserve(mesh.triangles.size());
  double total = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = mesh.positions[t.x], &b = mesh.positions[t.y], &c = mesh.positions[t.z];
    float area = 0.5f * glm::length(glm::cross(b - a, c - a));
    areas.push_back(area);
    total += area;
  }
  s.mesh_ = std::move(mesh);
  s.triangleAreas_ = DiscreteDistribution(areas);
  s.area_ = float(total);
  return s;
}

Shape Shape::sphere(Sphere sp) {
  Shape s;
  s.isSphere_ = true;
  s.sphere_ = sp;
  s.area_ = 4 * Pi * sp.radius * sp.radius;
  return s;
}

Bounds3 Shape::bounds() const {
  Bounds3 b;
  if (isSphere_) {
    b.extend(sphere_.center - Vec3(sphere_.radius));
    b.extend(sphere_.center + Vec3(sphere_.radius));
  } else {
    for (const auto& p : mesh_.positions) b.extend(p);
  }
  return b;
}

namespace {
Vec3 sphereErrorBound(const Vec3& center, const Vec3& pLocal) {
  // Reprojection onto the sphere costs gamma(5)|p_local| (pbrt-v4 §6.8.5), the
  // final translation to world space a further gamma(1)|p_world|.
  return gamma(5) * glm::abs(pLocal) + gamma(2) * (glm::abs(center) + glm::abs(pLocal));
}
}  // namespace

ShapeSample Shape::sphereSampleAt(const Vec3& dir) const {
  ShapeSample ss;
  Vec3 local = sphere_.radius * dir;
  ss.p = sphere_.center + local;
  ss.n = sphere_.flipNormals ? -dir : dir;
  ss.pError = sphereErrorBound(sphere_.center, local);
  ss.pdfArea = 1 / area_;
  return ss;
}

ShapeSample Shape::sampleArea(float uPick, Vec2 u) const {
  if (isSphere_) return sphereSampleAt(sampleUniformSphere(u));
  ShapeSample ss;
  size_t tri = triangleAreas_.sample(uPick);
  const auto& t = mesh_.triangles[tri];
  const Vec3 &a = mesh_.positions[t.x], &b = mesh_.positions[t.y], &c = mesh_.positions[t.z];
  Vec2 bc = sampleUniformTriangle(u);
  float b0 = 1 - bc.x - bc.y;
  ss.p = b0 * a + bc.x * b + bc.y * c;
  ss.pError = gamma(6) * (glm::abs(b0 * a) + glm::abs(bc.x * b) + glm::abs(bc.y * c));
  ss.n = glm::normalize(glm::cross(b - a, c - a));
  if (!mesh_.normals.empty()) {
    Vec3 ns = b0 * mesh_.normals[t.x] + bc.x * mesh_.normals[t.y] + bc.y * mesh_.normals[t.z];
    if (glm::dot(ns, ss.n) < 0) ss.n = -ss.n;
  }
  ss.pdfArea = 1 / area_;
  return ss;
}

ShapeSample Shape::sampleSolidAngle(const Vec3& ref, Vec2 u, float* pdf) const {
  Vec3 toCenter = sphere_.center - ref;
  float dist2 = glm::dot(toCenter, toCenter), r2 = sphere_.radius * sphere_.radius;
  if (dist2 <= r2 * 1.0001f) {  // inside or on the sphere: area sampling
    ShapeSample ss = sampleArea(0, u);
    Vec3 w = ss.p - ref;
    float d2 = glm::dot(w, w);
    float cos = d2 > 0 ? absDot(ss.n, w) / std::sqrt(d2) : 0;
    *pdf = cos > 0 ? ss.pdfArea * d2 / cos : 0;
    return ss;
  }
  // Uniform cone sampling (pbrt-v4 §6.2.4), with the small-angle Taylor
  // expansion so tiny or distant spheres do not lose all precision.
  float sin2ThetaMax = r2 / dist2;
  float cosThetaMax = safeSqrt(1 - sin2ThetaMax), oneMinusCosThetaMax = 1 - cosThetaMax;
  float cosTheta = (cosThetaMax - 1) * u.x + 1;
  float sin2Theta = 1 - cosTheta * cosTheta;
  if (sin2ThetaMax < 0.00068523f) {  // sin²(1.5°)
    sin2Theta = sin2ThetaMax * u.x;
    cosTheta = std::sqrt(1 - sin2Theta);
    oneMinusCosThetaMax = sin2ThetaMax / 2;
  }
  float dist = std::sqrt(dist2);
  float cosAlpha = sin2Theta / std::sqrt(sin2ThetaMax) + cosTheta * safeSqrt(1 - sin2Theta / sin2ThetaMax);
  float sinAlpha = safeSqrt(1 - cosAlpha * cosAlpha);
  float phi = u.y * 2 * Pi;
  Frame frame(-toCenter / dist);  // from the centre towards ref
  Vec3 nLocal(sinAlpha * std::cos(phi), sinAlpha * std::sin(phi), cosAlpha);
  *pdf = 1 / (2 * Pi * oneMinusCosThetaMax);
  return sphereSampleAt(frame.toWorld(nLocal));
}

float Shape::solidAnglePdf(const Vec3& ref, const Vec3& pOnShape, const Vec3& nOnShape) const {
  Vec3 toCenter = sphere_.center - ref;
  float dist2 = glm::dot(toCenter, toCenter), r2 = sphere_.radius * sphere_.radius;
  if (dist2 <= r2 * 1.0001f) {
    Vec3 w = pOnShape - ref;
    float d2 = glm::dot(w, w);
    float cos = d2 > 0 ? absDot(nOnShape, w) / std::sqrt(d2) : 0;
    return cos > 0 ? d2 / (cos * area_) : 0;
  }
  float sin2ThetaMax = r2 / dist2;
  float oneMinusCosThetaMax = 1 - safeSqrt(1 - sin2ThetaMax);
  if (sin2ThetaMax < 0.00068523f) oneMinusCosThetaMax = sin2ThetaMax / 2;
  return 1 / (2 * Pi * oneMinusCosThetaMax);
}

void Shape::fillInteraction(const Ray& ray, float t, int prim, float u, float v, SurfaceInteraction& si) const {
  si.t = t;
  si.primId = prim;
  si.wo = -ray.d;
  if (isSphere_) {
    // Reproject the hit onto the sphere in double precision.
    Vec3d o(ray.o), d(ray.d), c(sphere_.center);
    Vec3d local = o + double(t) * d - c;
    local *= double(sphere_.radius) / glm::length(local);
    Vec3 pLocal(local);
    si.p = Vec3(c + local);
    si.pError = sphereErrorBound(sphere_.center, pLocal);
    Vec3 n = glm::normalize(pLocal);
    if (sphere_.flipNormals) n = -n;
    si.ng = n;
    si.shading = Frame(n);
    // Mitsuba's sphere parametrisation (z up in the sphere's frame), from the
    // point, so that flipping the normals does not move a texture.
    Vec3 dir = glm::normalize(pLocal);
    float phi = std::atan2(dir.y, dir.x);
    si.uv = Vec2((phi < 0 ? phi + 2 * Pi : phi) * Inv2Pi, std::acos(glm::clamp(dir.z, -1.f, 1.f)) * InvPi);
    return;
  }
  const auto& tri = mesh_.triangles[prim];
  const Vec3 &a = mesh_.positions[tri.x], &b = mesh_.positions[tri.y], &c = mesh_.positions[tri.z];
  float b0 = 1 - u - v;
  // Barycentric interpolation error bound, pbrt-v4 §6.8.5 (Eq. 6.33). That
  // bound is per component, for pbrt's own intersection test; Embree's test
  // works in a ray-centred frame whose rounding mixes all three components,
  // so the bound is widened to the largest one in every direction. Without
  // this a face lying exactly on a coordinate plane (a box's top at y = 0)
  // has a zero bound across it, its rays start on the plane and re-hit it,
  // and every shadow ray is blocked: the face rendered black.
  si.p = b0 * a + u * b + v * c;
  si.pError = Vec3(maxComponent(gamma(7) * (glm::abs(b0 * a) + glm::abs(u * b) + glm::abs(v * c))));
  si.ng = glm::normalize(glm::cross(b - a, c - a));
  Vec3 ns = si.ng;
  if (!mesh_.normals.empty()) {
    Vec3 n = b0 * mesh_.normals[tri.x] + u * mesh_.normals[tri.y] + v * mesh_.normals[tri.z];
    float len = glm::length(n);
    if (len > 0) {
      ns = n / len;
      if (glm::dot(si.ng, ns) < 0) si.ng = -si.ng;  // the file's normals decide orientation
    }
  }
  si.shading = Frame(ns);
  si.uv = uvAt(prim, u, v);
}

Vec2 Shape::uvAt(int prim, float u, float v) const {
  if (isSphere_ || mesh_.uvs.empty()) return Vec2(u, v);
  const auto& tri = mesh_.triangles[size_t(prim)];
  return (1 - u - v) * mesh_.uvs[tri.x] + u * mesh_.uvs[tri.y] + v * mesh_.uvs[tri.z];
}

void Shape::surfaceTangents(SurfaceInteraction& si) const {
  if (isSphere_) {
    // p = c + r (sin θ cos φ, sin θ sin φ, cos θ) with u = φ/2π, v = θ/π.
    Vec3 d = glm::normalize(si.p - sphere_.center);
    float sinTheta = std::sqrt(std::max(0.f, 1 - d.z * d.z));
    float phi = std::atan2(d.y, d.x), cosPhi = std::cos(phi), sinPhi = std::sin(phi);
    si.dpdu = 2 * Pi * sphere_.radius * Vec3(-sinTheta * sinPhi, sinTheta * cosPhi, 0);
    si.dpdv = Pi * sphere_.radius * Vec3(d.z * cosPhi, d.z * sinPhi, -sinTheta);
    return;
  }
  const auto& tri = mesh_.triangles[size_t(si.primId)];
  const Vec3 &a = mesh_.positions[tri.x], &b = mesh_.positions[tri.y], &c = mesh_.positions[tri.z];
  // Without uvs, (u, v) are the barycentrics of b and c: p = a + u (b - a) + v (c - a).
  si.dpdu = b - a, si.dpdv = c - a;
  if (mesh_.uvs.empty()) return;
  Vec2 duv02 = mesh_.uvs[tri.x] - mesh_.uvs[tri.z], duv12 = mesh_.uvs[tri.y] - mesh_.uvs[tri.z];
  Vec3 dp02 = a - c, dp12 = b - c;
  float det = duv02.x * duv12.y - duv02.y * duv12.x;
  if (std::abs(det) < 1e-12f) return;  // degenerate uvs: the edges stand in
  si.dpdu = (duv12.y * dp02 - duv02.y * dp12) / det;
  si.dpdv = (duv02.x * dp12 - duv12.x * dp02) / det;
}

}  // namespace lb
