// Manifold next-event estimation's Newton solver and generalised geometry
// term; the equations are in specular_chain.h.
#include "integrators/manifold/specular_chain.h"

#include <algorithm>
#include <cmath>
#include "core/bsdfs/conductor.h"
#include "core/bsdfs/dielectric.h"
#include "core/bsdfs/fresnel.h"

namespace lb {
namespace {

// A chain vertex's own surface around the point where a ray met it, in double
// precision: the triangle's plane with its interpolated shading normal, or
// the sphere. Tangent coordinates (u, v) along the orthonormal e1, e2 at the
// anchor p measure area there.
struct LocalSurface {
  bool sphere = false;
  Vec3d center{0.0};
  double radius = 0;
  bool flip = false;
  Vec3d a{0.0}, b{0.0}, c{0.0};     // the triangle
  Vec3d na{0.0}, nb{0.0}, nc{0.0};  // its vertex normals (smooth) …
  bool smooth = false;
  Vec3d ng{0.0};                    // … or its winding's normal
  double eta = 1;                   // interior over exterior
  bool mirror = false;              // a smooth conductor: reflects (its Fresnel below)
  ConductorFresnel fresnel;
  Vec3d p{0.0}, e1{0.0}, e2{0.0};

  Vec3d at(double u, double v) const {
    if (sphere) return center + radius * glm::normalize(p - center + u * e1 + v * e2);
    return p + u * e1 + v * e2;
  }
  Vec3d geometricNormal(const Vec3d& q) const { return sphere ? glm::normalize(q - center) : ng; }
  // Moves the anchor to q, a point of the surface (a sphere's tangents turn with it).
  void reanchor(const Vec3d& q) {
    p = q;
    if (!sphere) return;
    Vec3d radial = glm::normalize(p - center);
    Frame f{Vec3(radial)};
    e1 = glm::normalize(Vec3d(f.s) - glm::dot(Vec3d(f.s), radial) * radial);
    e2 = glm::cross(radial, e1);
  }
  // Where the ray o + t d (d unit) meets the surface nearest to `guess` (a
  // float hit of the same ray), in double precision; none if it misses.
  std::optional<Vec3d> intersect(const Vec3d& o, const Vec3d& d, const Vec3d& guess) const {
    if (!sphere) {
      double den = glm::dot(d, ng);
      if (den == 0) return std::nullopt;
      return o + glm::dot(a - o, ng) / den * d;
    }
    Vec3d oc = o - center;
    double b = glm::dot(oc, d), disc = b * b - (glm::dot(oc, oc) - radius * radius);
    if (disc < 0) return std::nullopt;
    double root = std::sqrt(disc), tGuess = glm::dot(guess - o, d);
    double t = std::abs(-b - root - tGuess) < std::abs(-b + root - tGuess) ? -b - root : -b + root;
    return o + t * d;
  }
  Vec3d normal(const Vec3d& q) const {
    if (sphere) return (flip ? -1.0 : 1.0) * glm::normalize(q - center);
    if (!smooth) return ng;
    // Barycentrics of q in the triangle's plane (linear, so the normal is the
    // same interpolation fillInteraction makes, continued past the edges).
    Vec3d v0 = b - a, v1 = c - a, v2 = q - a;
    double d00 = glm::dot(v0, v0), d01 = glm::dot(v0, v1), d11 = glm::dot(v1, v1);
    double d20 = glm::dot(v2, v0), d21 = glm::dot(v2, v1), den = d00 * d11 - d01 * d01;
    double u = (d11 * d20 - d01 * d21) / den, v = (d00 * d21 - d01 * d20) / den;
    return glm::normalize((1 - u - v) * na + u * nb + v * nc);
  }
};

std::optional<LocalSurface> localSurface(const Scene& scene, const SurfaceInteraction& si) {
  const auto* glass = dynamic_cast<const SmoothDielectric*>(si.material);
  const auto* mirror = dynamic_cast<const SmoothConductor*>(si.material);
  // Instanced shapes are stored in their object's space; normal and bump
  // maps move the shading normal off the interpolation differentiated here.
  if ((!glass && !mirror) || si.material->perturbsShading() || si.shapeId < 0 ||
      size_t(si.shapeId) >= scene.shapes().size())
    return std::nullopt;
  const Shape& shape = scene.shapes()[size_t(si.shapeId)];
  LocalSurface s;
  if (glass) s.eta = glass->eta();
  if (mirror) s.mirror = true, s.fresnel = mirror->fresnel();
  s.p = Vec3d(si.p);
  if (shape.isSphere()) {
    s.sphere = true;
    s.center = Vec3d(shape.sphereData().center);
    s.radius = shape.sphereData().radius;
    s.flip = shape.sphereData().flipNormals;
    s.reanchor(s.p);
    return s;
  }
  const TriangleMesh& mesh = shape.triangleMesh();
  const auto& tri = mesh.triangles[size_t(si.primId)];
  s.a = Vec3d(mesh.positions[tri.x]), s.b = Vec3d(mesh.positions[tri.y]), s.c = Vec3d(mesh.positions[tri.z]);
  s.ng = glm::normalize(glm::cross(s.b - s.a, s.c - s.a));
  if (!mesh.normals.empty()) {
    s.smooth = true;
    s.na = Vec3d(mesh.normals[tri.x]), s.nb = Vec3d(mesh.normals[tri.y]), s.nc = Vec3d(mesh.normals[tri.z]);
  }
  s.e1 = glm::normalize(s.b - s.a);
  s.e2 = glm::cross(s.ng, s.e1);
  return s;
}

constexpr int MaxChain = ManifoldConnection::MaxChain;

struct Chain {
  int k = 0;
  LocalSurface surfaces[MaxChain];
  SurfaceInteraction hits[MaxChain];
};

// c_i at the point q of surface s, between its neighbours (the header's
// constraint); false where the half vector vanishes.
bool halfVectorConstraint(const LocalSurface& s, const Vec3d& prev, const Vec3d& q, const Vec3d& next, double* c) {
  Vec3d wi = glm::normalize(prev - q), wo = glm::normalize(next - q), n = s.normal(q);
  // A mirror's constraint is the ordinary half vector (η = 1 on both sides).
  double etaI = glm::dot(wi, n) > 0 ? 1 : s.eta, etaO = glm::dot(wo, n) > 0 ? 1 : s.eta;
  Vec3d h = etaI * wi + etaO * wo;
  double length = glm::length(h);
  if (!(length > 1e-12)) return false;
  h /= length;
  Vec3d tangent = glm::normalize(s.e1 - glm::dot(s.e1, n) * n), bitangent = glm::cross(n, tangent);
  c[0] = glm::dot(h, tangent);
  c[1] = glm::dot(h, bitangent);
  return true;
}

// The whole constraint vector for vertex positions x[0 … k−1] between x0 and y.
bool constraints(const Chain& ch, const Vec3d& x0, const Vec3d* x, const Vec3d& y, double* c) {
  for (int i = 0; i < ch.k; ++i) {
    const Vec3d& prev = i == 0 ? x0 : x[i - 1];
    const Vec3d& next = i == ch.k - 1 ? y : x[i + 1];
    if (!halfVectorConstraint(ch.surfaces[i], prev, x[i], next, c + 2 * i)) return false;
  }
  return true;
}

// A (∂c/∂x_1…x_k, columns 2j, 2j + 1 for x_j's tangent coordinates) and B
// (∂c/∂x_0, columns 0 and 1 along x_0's tangents t0, t1), by central
// differences, padded to 4 × 4 (identity, zero) for k = 1. GLM's matrices are
// column-major: m[column][row].
bool derivatives(const Chain& ch, const Vec3d& x0, const Vec3d (&t0)[2], const Vec3d& y, glm::dmat4* A,
                 glm::dmat4* B) {
  Vec3d x[MaxChain];
  for (int i = 0; i < ch.k; ++i) x[i] = ch.surfaces[i].p;
  *A = glm::dmat4(1.0);
  *B = glm::dmat4(0.0);
  double cPlus[2 * MaxChain], cMinus[2 * MaxChain];
  // Steps of 1e-5 of the shortest adjacent segment: central differences'
  // truncation (h²) and rounding (ε/h) errors are then both near 1e-10.
  auto step = [&](const Vec3d& q, const Vec3d& prev, const Vec3d& next) {
    return 1e-5 * std::min(glm::length(q - prev), glm::length(next - q));
  };
  for (int j = 0; j < ch.k; ++j) {
    double h = step(x[j], j == 0 ? x0 : x[j - 1], j == ch.k - 1 ? y : x[j + 1]);
    for (int d = 0; d < 2; ++d) {
      Vec3d moved[MaxChain];
      std::copy(x, x + ch.k, moved);
      moved[j] = ch.surfaces[j].at(d == 0 ? h : 0, d == 1 ? h : 0);
      if (!constraints(ch, x0, moved, y, cPlus)) return false;
      moved[j] = ch.surfaces[j].at(d == 0 ? -h : 0, d == 1 ? -h : 0);
      if (!constraints(ch, x0, moved, y, cMinus)) return false;
      for (int r = 0; r < 2 * ch.k; ++r) (*A)[2 * j + d][r] = (cPlus[r] - cMinus[r]) / (2 * h);
    }
  }
  double h = 1e-5 * glm::length(x[0] - x0);
  for (int d = 0; d < 2; ++d) {
    if (!constraints(ch, x0 + h * t0[d], x, y, cPlus) || !constraints(ch, x0 - h * t0[d], x, y, cMinus)) return false;
    for (int r = 0; r < 2 * ch.k; ++r) (*B)[d][r] = (cPlus[r] - cMinus[r]) / (2 * h);
  }
  return true;
}

// Moves each vertex by its tangent step and projects the chain back onto the
// scene by tracing from x_0 through the moved points: false if a ray misses
// or meets another shape than the vertex had. The scene's ray finds the
// triangle (in float); the vertex is then that ray's intersection with the
// triangle's plane or the sphere in double precision, so that the constraint
// can fall below float's rounding on short segments (a caustic beside a
// sphere's contact point).
bool project(const Scene& scene, const SurfaceInteraction& x0, const Vec3d& p0, const Chain& ch,
             const glm::dvec4& step, Chain& out) {
  out.k = ch.k;
  const SurfaceInteraction* from = &x0;
  Vec3d origin = p0;
  for (int j = 0; j < ch.k; ++j) {
    Vec3d target = ch.surfaces[j].at(step[2 * j], step[2 * j + 1]);
    Vec3d d = glm::normalize(target - origin);
    SurfaceInteraction hit;
    if (!scene.intersect(from->spawnRay(Vec3(d)), hit) || hit.shapeId != ch.hits[j].shapeId) return false;
    auto surface = localSurface(scene, hit);
    if (!surface) return false;
    auto exact = surface->intersect(origin, d, Vec3d(hit.p));
    if (!exact || glm::length(*exact - Vec3d(hit.p)) > 1e-3 * glm::length(*exact - origin)) return false;
    surface->reanchor(*exact);
    out.surfaces[j] = *surface;
    out.hits[j] = hit;
    from = &out.hits[j];
    origin = *exact;
  }
  return true;
}

}  // namespace

bool seedSpecularChain(const Scene& scene, const SurfaceInteraction& x0, const Vec3& y, int maxChain,
                       SurfaceInteraction* seeds, int* k) {
  *k = 0;
  const SurfaceInteraction* from = &x0;
  for (;;) {
    Vec3 toY = y - from->p;
    float distance = glm::length(toY);
    Ray ray = from->spawnRay(toY / distance);
    ray.tMax = distance * (1 - ShadowEpsilon);
    SurfaceInteraction hit;
    if (!scene.intersect(ray, hit)) return true;
    // A straight segment can only cross refracting surfaces: a mirror on it blocks it.
    auto surface = localSurface(scene, hit);
    if (*k == maxChain || !surface || surface->mirror) return false;
    seeds[(*k)++] = hit;
    from = &seeds[*k - 1];
  }
}

std::optional<ManifoldConnection> connectThroughSpecularChain(const Scene& scene, const SurfaceInteraction& x0,
                                                              const Vec3& y, const ManifoldSettings& settings) {
  SurfaceInteraction seeds[MaxChain];
  int k = 0;
  if (!seedSpecularChain(scene, x0, y, std::min(settings.maxChain, MaxChain), seeds, &k) || k == 0)
    return std::nullopt;
  return solveSpecularChain(scene, x0, y, seeds, k, settings);
}

bool isSpecularChainSurface(const Scene& scene, const SurfaceInteraction& si) {
  return localSurface(scene, si).has_value();
}

std::optional<ManifoldConnection> solveSpecularChain(const Scene& scene, const SurfaceInteraction& x0,
                                                     const Vec3& yFloat, const SurfaceInteraction* seeds, int k,
                                                     const ManifoldSettings& settings) {
  Chain ch;
  ch.k = k;
  for (int i = 0; i < ch.k; ++i) {
    auto surface = localSurface(scene, seeds[i]);
    if (!surface) return std::nullopt;
    ch.hits[i] = seeds[i];
    ch.surfaces[i] = *surface;
  }
  const Vec3d p0(x0.p), y(yFloat), n0(glm::normalize(x0.ng));
  Frame frame0{Vec3(n0)};
  const Vec3d t0[2] = {glm::normalize(Vec3d(frame0.s)), glm::normalize(glm::cross(n0, Vec3d(frame0.s)))};

  // Newton's method (the header), with Hanika et al.'s step control: halve
  // the step where the projection fails, double it (up to 1) where it works.
  ManifoldConnection result;
  double beta = 1;
  glm::dmat4 A, B;
  bool converged = false;
  for (result.iterations = 0; result.iterations < settings.maxIterations; ++result.iterations) {
    Vec3d x[MaxChain];
    for (int i = 0; i < ch.k; ++i) x[i] = ch.surfaces[i].p;
    double c[2 * MaxChain];
    if (!constraints(ch, p0, x, y, c)) return std::nullopt;
    double worst = 0;
    for (int r = 0; r < 2 * ch.k; ++r) worst = std::max(worst, std::abs(c[r]));
    if (worst < settings.tolerance) {
      converged = true;
      break;
    }
    if (!derivatives(ch, p0, t0, y, &A, &B)) return std::nullopt;
    double det = glm::determinant(A);
    if (!(std::abs(det) > 0) || !std::isfinite(det)) return std::nullopt;
    glm::dvec4 cv(0.0);
    for (int r = 0; r < 2 * ch.k; ++r) cv[r] = c[r];
    glm::dvec4 delta = -(glm::inverse(A) * cv);
    // No vertex moves further than half its shortest segment in one step.
    double limit = Infinity;
    for (int i = 0; i < ch.k; ++i) {
      double len = std::hypot(delta[2 * i], delta[2 * i + 1]);
      double room = 0.5 * std::min(glm::length(x[i] - (i == 0 ? p0 : x[i - 1])),
                                   glm::length((i == ch.k - 1 ? y : x[i + 1]) - x[i]));
      if (len > 0) limit = std::min(limit, room / len);
    }
    Chain moved;
    if (project(scene, x0, p0, ch, delta * std::min(beta, limit), moved)) {
      ch = moved;
      beta = std::min(1.0, 2 * beta);
    } else if ((beta *= 0.5) < 1e-4) {
      return std::nullopt;
    }
  }
  if (!converged) return std::nullopt;

  // Every glass vertex refracts (its neighbours on opposite sides of both
  // normals), every mirror reflects (on one side of both).
  Vec3d x[MaxChain];
  for (int i = 0; i < ch.k; ++i) x[i] = ch.surfaces[i].p;
  result.throughput = Color(1.f);
  for (int i = 0; i < ch.k; ++i) {
    const LocalSurface& surface = ch.surfaces[i];
    const Vec3d& prev = i == 0 ? p0 : x[i - 1];
    const Vec3d& next = i == ch.k - 1 ? y : x[i + 1];
    Vec3d wi = glm::normalize(prev - x[i]), wo = glm::normalize(next - x[i]);
    Vec3d n = surface.normal(x[i]), ng = surface.geometricNormal(x[i]);
    double side = surface.mirror ? 1 : -1;  // the sign dot(wi, ·) dot(wo, ·) must have
    if (!(side * glm::dot(wi, n) * glm::dot(wo, n) > 0) || !(side * glm::dot(wi, ng) * glm::dot(wo, ng) > 0))
      return std::nullopt;
    if (surface.mirror)
      result.throughput *= surface.fresnel(float(std::abs(glm::dot(wi, n))));
    else
      result.throughput *= 1 - fresnelDielectric(float(glm::dot(wi, n)), float(surface.eta));
  }
  if (!derivatives(ch, p0, t0, y, &A, &B)) return std::nullopt;
  glm::dmat4 D = -(glm::inverse(A) * B);  // ∂x/∂x_0: rows 2j, 2j + 1 are x_j's
  const int last = 2 * (ch.k - 1);
  double detLast = D[0][last] * D[1][last + 1] - D[1][last] * D[0][last + 1];
  Vec3d toLast = x[ch.k - 1] - y;
  double r2 = glm::dot(toLast, toLast);
  double cosLast = std::abs(glm::dot(toLast, ch.surfaces[ch.k - 1].geometricNormal(x[ch.k - 1]))) / std::sqrt(r2);
  result.geometry = cosLast / r2 * std::abs(detLast);
  if (!std::isfinite(result.geometry) || !(result.geometry > 0)) return std::nullopt;
  result.k = ch.k;
  for (int i = 0; i < ch.k; ++i) result.vertices[i] = ch.hits[i];
  result.wi = Vec3(glm::normalize(x[0] - p0));
  return result;
}

}  // namespace lb
