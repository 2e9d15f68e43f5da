// The manifold solver (integrators/manifold/specular_chain.h), checked
// against the forward map it inverts, written here independently: light
// leaving y in a direction, refracted by Snell's law (in vector form, double
// precision) at every glass surface the scene's rays meet, with the shading
// normal the scene reports, lands on the floor.
//  * Newton's method converges to a chain that map takes from y to x_0: a
//    flat water surface (one refraction), a glass sphere (two), and the
//    water pool's wavy mesh with interpolated normals (one, where the
//    normal's derivative across the triangle shapes the solution);
//  * the generalised geometry term |dω_y/dA_0| is the inverse of the area on
//    the floor that a small cone of directions from y lands on (central
//    differences of the forward map).
// Measured: landings within 1.4e-6 of x_0, geometry terms within 0.13 % of
// the mapped areas. Seen failing with the solver's mesh normal taken flat
// (the pool's chain lands 4e-3 from x_0, and its geometry term is 12 % off)
// and with the geometry term times 1.05.
#include <gtest/gtest.h>

#include <optional>
#include "core/bsdfs/conductor.h"
#include "core/bsdfs/dielectric.h"
#include "integrators/manifold/specular_chain.h"
#include "tests/support/render_helpers.h"

namespace lb::test {
namespace {

// Snell's law: the direction d continuing through an interface of normal n
// (either side) from index etaFrom into etaTo; none on total internal reflection.
std::optional<Vec3d> snell(const Vec3d& d, Vec3d n, double etaFrom, double etaTo) {
  if (glm::dot(d, n) > 0) n = -n;  // n against the travel direction
  double ratio = etaFrom / etaTo, cosI = -glm::dot(d, n);
  double sin2T = ratio * ratio * (1 - cosI * cosI);
  if (sin2T >= 1) return std::nullopt;
  return glm::normalize(ratio * d + (ratio * cosI - std::sqrt(1 - sin2T)) * n);
}

// Where light leaving y along d first meets a surface that is not glass
// (starting 1e-3 along d: y may lie on the light's own surface).
std::optional<Vec3d> land(const Scene& scene, const Vec3d& y, Vec3d d) {
  Ray ray{Vec3(y + 1e-3 * d), Vec3(d), Infinity};
  for (int bounce = 0; bounce < 8; ++bounce) {
    SurfaceInteraction si;
    if (!scene.intersect(ray, si)) return std::nullopt;
    Vec3d n(si.shading.n);
    if (dynamic_cast<const SmoothConductor*>(si.material)) {  // the law of reflection
      d = d - 2 * glm::dot(d, n) * n;
      ray = si.spawnRay(Vec3(d));
      continue;
    }
    const auto* glass = dynamic_cast<const SmoothDielectric*>(si.material);
    if (!glass) return Vec3d(si.p);
    bool entering = glm::dot(d, n) < 0;  // the shading normal points out of the glass
    auto next = entering ? snell(d, n, 1, glass->eta()) : snell(d, n, glass->eta(), 1);
    if (!next) return std::nullopt;
    d = *next;
    ray = si.spawnRay(Vec3(d));
  }
  return std::nullopt;
}

SurfaceInteraction hitAlong(const Scene& scene, Vec3 from, Vec3 direction = Vec3(0, -1, 0)) {
  SurfaceInteraction si;
  EXPECT_TRUE(scene.intersect({from, direction, Infinity}, si));
  return si;
}

struct ChainCase {
  std::string name;
  SceneFile scene;
  SurfaceInteraction x0;
  Vec3 y;
  int k;
};

std::vector<ChainCase> chainCases() {
  std::vector<ChainCase> cases;
  // Water over a floor; x_0 found from below the surface.
  SceneFile flat = loadSceneFromString(
      "camera: {position: [0, 3, 3], look_at: [0, 0, 0], fov: 40}\n"
      "materials: {floor: {type: diffuse, albedo: 0.8}, water: {type: dielectric, ior: 1.33}}\n"
      "shapes:\n"
      "  - {type: rectangle, material: floor, transform: {scale: 3, rotate_x: -90, translate: [0, -1, 0]}}\n"
      "  - {type: rectangle, material: water, transform: {scale: 3, rotate_x: -90}}\n"
      "lights: [{type: point, position: [1, 2, -0.5], intensity: 1}]\n",
      "flat-water.yaml");
  SurfaceInteraction x0 = hitAlong(*flat.scene, {0.2f, -0.5f, 0.1f});
  cases.push_back({"flat water", std::move(flat), x0, Vec3(1, 2, -0.5), 1});
  // A glass slab (0.2 thick) over a floor: two refractions at parallel faces.
  SceneFile slab = loadSceneFromString(
      "camera: {position: [0, 3, 3], look_at: [0, 0, 0], fov: 40}\n"
      "materials: {floor: {type: diffuse, albedo: 0.8}, glass: {type: dielectric, ior: 1.5}}\n"
      "shapes:\n"
      "  - {type: rectangle, material: floor, transform: {scale: 3, rotate_x: -90, translate: [0, -1, 0]}}\n"
      "  - {type: box, material: glass, transform: {scale: [1.5, 0.1, 1.5]}}\n"
      "lights: [{type: point, position: [0.3, 1.5, -0.2], intensity: 1}]\n",
      "glass-slab.yaml");
  x0 = hitAlong(*slab.scene, {0.6f, -0.5f, 0.4f});
  cases.push_back({"glass slab", std::move(slab), x0, Vec3(0.3f, 1.5f, -0.2f), 2});
  // The caustic scene's sphere and light, x_0 in the caustic beside the
  // sphere's contact point (found from below the floor).
  SceneFile sphere = loadShippedScene("caustic-glass-sphere", 64, 48);
  x0 = hitAlong(*sphere.scene, {-0.12f, -0.5f, 0.06f}, Vec3(0, 1, 0));
  cases.push_back({"glass sphere", std::move(sphere), x0, Vec3(0.41f, 3, -0.19f), 2});
  // The water pool's height-field mesh (smooth normals) under its sun.
  SceneFile pool = loadShippedScene("water-pool", 64, 48);
  x0 = hitAlong(*pool.scene, {0.1f, -0.3f, 0.2f});
  Vec3 sun(1.5f, 6, -2);
  cases.push_back({"water pool", std::move(pool), x0, sun + 0.25f * glm::normalize(x0.p - sun), 1});
  return cases;
}

TEST(SpecularChain, NewtonConvergesToTheChainSnellsLawTakesToX0) {
  for (const ChainCase& c : chainCases()) {
    auto chain = connectThroughSpecularChain(*c.scene.scene, c.x0, c.y, {});
    ASSERT_TRUE(chain) << c.name;
    EXPECT_EQ(chain->k, c.k) << c.name;
    const Vec3d y(c.y), xk(chain->vertices[chain->k - 1].p);
    auto landed = land(*c.scene.scene, y, glm::normalize(xk - y));
    ASSERT_TRUE(landed) << c.name;
    // The solver's tolerance (1e-5 on the half vector) moves the landing
    // point by about 1e-5 of the path's length (a few units here).
    EXPECT_LT(glm::length(*landed - Vec3d(c.x0.p)), 2e-4) << c.name << ": landed " << glm::length(*landed - Vec3d(c.x0.p))
                                                          << " from x0 after " << chain->iterations << " steps";
    EXPECT_GT(chain->throughput.g, 0.8f) << c.name;
    EXPECT_LT(chain->throughput.g, 1.f) << c.name;
  }
}

TEST(SpecularChain, GeometryTermIsTheInverseOfTheMappedArea) {
  for (const ChainCase& c : chainCases()) {
    auto chain = connectThroughSpecularChain(*c.scene.scene, c.x0, c.y, {});
    ASSERT_TRUE(chain) << c.name;
    const Vec3d y(c.y), w = glm::normalize(Vec3d(chain->vertices[chain->k - 1].p) - y);
    Frame frame{Vec3(w)};
    const Vec3d u(frame.s), v(frame.t);
    // A cone of 1e-4 rad: the landing points move by ~1e-4 of the path's
    // length, well above float rounding (1e-7) and within one triangle of
    // the pool's mesh; the differences' own error is ~1e-8.
    const double delta = 1e-4;
    auto at = [&](double a, double b) { return land(*c.scene.scene, y, glm::normalize(w + a * u + b * v)); };
    auto ap = at(delta, 0), am = at(-delta, 0), bp = at(0, delta), bm = at(0, -delta);
    ASSERT_TRUE(ap && am && bp && bm) << c.name;
    double mappedArea = glm::length(glm::cross(*ap - *am, *bp - *bm)) / (4 * delta * delta);  // dA_0/dω_y
    EXPECT_NEAR(chain->geometry * mappedArea, 1.0, 0.01)
        << c.name << ": |dω/dA| " << chain->geometry << ", mapped area per solid angle " << mappedArea;
  }
}

// Specular manifold sampling's chains may reflect: seeded on a flat mirror,
// Newton's method reaches
// the chain the law of reflection takes from y to x_0, and its geometry term
// is again the mapped area's inverse. MNEE's straight segment cannot reflect:
// a mirror on it blocks it.
TEST(SpecularChain, MirrorChainsReflectAndTheirTermIsTheMappedArea) {
  SceneFile flat = loadSceneFromString(
      "camera: {position: [0, 3, 3], look_at: [0, 0, 0], fov: 40}\n"
      "materials: {floor: {type: diffuse, albedo: 0.8}, mirror: {type: conductor}}\n"
      "shapes:\n"
      "  - {type: rectangle, material: floor, transform: {scale: 3, rotate_x: -90}}\n"
      "  - {type: rectangle, material: mirror, transform: {scale: 1, translate: [0, 0.5, -1]}}\n"
      "lights: [{type: point, position: [0.5, 1.5, 0.5], intensity: 1}]\n",
      "mirror.yaml");
  struct MirrorCase {
    const char* name;
    const SceneFile& scene;
    Vec3 x0From, seedTowards, y;
  };
  for (const MirrorCase& c : {MirrorCase{"flat mirror", flat, {-0.3f, 1, 0.2f}, {0, 0.6f, -1}, {0.5f, 1.5f, 0.5f}}}) {
    const Scene& scene = *c.scene.scene;
    SurfaceInteraction x0 = hitAlong(scene, c.x0From);
    SurfaceInteraction seed;
    ASSERT_TRUE(scene.intersect(x0.spawnRay(glm::normalize(c.seedTowards - x0.p)), seed)) << c.name;
    ASSERT_TRUE(isSpecularChainSurface(scene, seed)) << c.name;
    auto chain = solveSpecularChain(scene, x0, c.y, &seed, 1, {});
    ASSERT_TRUE(chain) << c.name;
    const Vec3d y(c.y), w = glm::normalize(Vec3d(chain->vertices[0].p) - y);
    auto landed = land(scene, y, w);
    ASSERT_TRUE(landed) << c.name;
    EXPECT_LT(glm::length(*landed - Vec3d(x0.p)), 2e-4) << c.name;
    Frame frame{Vec3(w)};
    const double delta = 1e-4;
    auto at = [&](double a, double b) { return land(scene, y, glm::normalize(w + a * Vec3d(frame.s) + b * Vec3d(frame.t))); };
    auto ap = at(delta, 0), am = at(-delta, 0), bp = at(0, delta), bm = at(0, -delta);
    ASSERT_TRUE(ap && am && bp && bm) << c.name;
    double mappedArea = glm::length(glm::cross(*ap - *am, *bp - *bm)) / (4 * delta * delta);
    EXPECT_NEAR(chain->geometry * mappedArea, 1.0, 0.01) << c.name;
    // The straight segment from x_0 through the mirror to a point behind it: blocked.
    EXPECT_FALSE(connectThroughSpecularChain(scene, x0, Vec3(chain->vertices[0].p) + 0.5f * (Vec3(chain->vertices[0].p) - x0.p), {}))
        << c.name;
  }
}

TEST(SpecularChain, NoChainWhereTheSegmentCrossesNoGlassOrAnOpaqueSurface) {
  auto cases = chainCases();
  const ChainCase& flat = cases[0];
  // Below the water: nothing to solve (ordinary next-event estimation's).
  EXPECT_FALSE(connectThroughSpecularChain(*flat.scene.scene, flat.x0, Vec3(0.5f, -0.5f, 0), {}));
  // Through the floor: blocked.
  EXPECT_FALSE(connectThroughSpecularChain(*flat.scene.scene, flat.x0, Vec3(0.5f, -2, 0), {}));
  // The sphere's chain has two vertices: refused with one allowed.
  const ChainCase& sphere = cases[2];
  ManifoldSettings one;
  one.maxChain = 1;
  EXPECT_FALSE(connectThroughSpecularChain(*sphere.scene.scene, sphere.x0, sphere.y, one));
}

}  // namespace
}  // namespace lb::test
