// Objects and instances (issue 35; pbrt-v4's ObjectBegin/ObjectInstance,
// core/scene.h): an instance hits where the same shapes flattened into the
// world do, with the same normals, uvs and sides, its points' error bounds
// cover the difference, a sphere under a non-uniform instance scale is the
// exact ellipsoid, and renders agree: instanced against flattened, and path
// tracing against BDPT through a masked object.
#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>
#include <cstring>
#include <sstream>
#include "core/error.h"
#include "core/rng.h"
#include "core/scene.h"
#include "core/scene_loader.h"
#include "tests/support/render_helpers.h"
#include "tests/support/repeats.h"

namespace lb {
namespace {

// A transform as the scene file writes it: {matrix: 16 numbers, row by row}.
std::string matrixYaml(const glm::mat4& m) {
  std::ostringstream s;
  s.precision(9);
  s << "{matrix: [";
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) s << (row + col ? ", " : "") << m[col][row];
  s << "]}";
  return s.str();
}

glm::mat4 trs(Vec3 translate, float degreesY, Vec3 scale) {
  glm::mat4 m = glm::translate(glm::mat4(1.f), translate);
  m = glm::rotate(m, glm::radians(degreesY), Vec3(0, 1, 0));
  return glm::scale(m, scale);
}

// Two objects, each placed twice: "blocks" (a box and a rectangle, the
// second placement mirrored and non-uniformly scaled) and "ball" (a sphere,
// uniformly scaled and not rotated, so that a flattened scene can hold it
// too: a rotated instance's sphere turns its uv with it, as it should).
const glm::mat4 BoxInObject = trs({0, 0.5f, 0}, 10, {0.5f, 0.5f, 0.5f});
const glm::mat4 RectInObject = trs({0, 0, 0.8f}, -20, {0.7f, 0.4f, 1});
const glm::mat4 BlockPlacements[2] = {trs({-1.2f, 0, 0}, 30, {1, 1, 1}), trs({1.3f, 0.2f, -0.5f}, -50, {-1, 0.6f, 1.5f})};
const glm::mat4 BallPlacements[2] = {trs({0, 1.4f, 0.3f}, 0, {1, 1, 1}), trs({0.2f, -0.9f, 1}, 0, {1.6f, 1.6f, 1.6f})};
const Vec3 BallCenter(0.1f, 0, 0);
const float BallRadius = 0.35f;

const std::string Header =
    "camera: {position: [0, 0.6, 5], look_at: [0, 0.2, 0], fov: 45}\n"
    "film: {width: 24, height: 24}\n"
    "integrator: {name: path, max_depth: 5}\n"
    "materials:\n"
    "  white: {type: diffuse, albedo: 0.7}\n"
    "  grid: {type: diffuse, texture: {type: checkerboard, color0: 0.2, color1: 0.8, uv_transform: [4, 0, 0, 0, 4, 0]}}\n"
    "  shiny: {type: conductor, roughness: 0.2}\n";
const std::string Room =
    "  - {type: rectangle, material: white, transform: {scale: 4, rotate_x: -90, translate: [0, -1.5, 0]}}\n"
    "  - {type: rectangle, material: white, transform: {scale: 4, translate: [0, 0, -2]}}\n"
    "  - {type: rectangle, material: none, emission: 8, transform: {scale: 0.6, rotate_x: 90, translate: [0, 2.5, 0.5]}}\n";

std::string instancedScene() {
  std::string s = Header + "objects:\n  blocks:\n";
  s += "    - {type: box, material: grid, transform: " + matrixYaml(BoxInObject) + "}\n";
  s += "    - {type: rectangle, material: white, transform: " + matrixYaml(RectInObject) + "}\n";
  s += "  ball:\n    - {type: sphere, material: shiny, center: [0.1, 0, 0], radius: 0.35}\n";
  s += "shapes:\n" + Room;
  for (const glm::mat4& m : BlockPlacements) s += "  - {type: instance, object: blocks, transform: " + matrixYaml(m) + "}\n";
  for (const glm::mat4& m : BallPlacements) s += "  - {type: instance, object: ball, transform: " + matrixYaml(m) + "}\n";
  return s;
}

// The same shapes with each placement multiplied into their transforms.
std::string flattenedScene() {
  std::string s = Header + "shapes:\n" + Room;
  for (const glm::mat4& m : BlockPlacements) {
    s += "  - {type: box, material: grid, transform: " + matrixYaml(m * BoxInObject) + "}\n";
    s += "  - {type: rectangle, material: white, transform: " + matrixYaml(m * RectInObject) + "}\n";
  }
  for (const glm::mat4& m : BallPlacements) {
    Vec3 c(m * glm::vec4(BallCenter, 1));
    std::ostringstream ball;
    ball.precision(9);
    ball << "  - {type: sphere, material: shiny, center: [" << c.x << ", " << c.y << ", " << c.z
         << "], radius: " << BallRadius * glm::length(Vec3(m[0])) << "}\n";
    s += ball.str();
  }
  return s;
}

Vec3 randomDirection(Pcg32& rng) {
  float z = 1 - 2 * rng.next1D(), phi = 2 * Pi * rng.next1D(), r = std::sqrt(std::max(0.f, 1 - z * z));
  return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

// How far apart the two scenes' surfaces may lie at a hit p: each vertex is
// a float transform of the same object vertex v, the instanced one through
// the shape's transform and then the placement's, the flattened one through
// their product (itself rounded, and written with 9 digits). Each step is
// within γ(3) of its magnitudes (pbrt-v4 §6.8.6), so γ(9) of the chain
// |placement| (|shape| |v| + |t_shape|) + |t_placement| bounds them all.
Vec3 flatteningRounding(int shapeId, const Vec3& p) {
  if (shapeId < 3) return Vec3(0.f);  // the room: the same shapes in both files
  glm::mat4 placement = shapeId < 7 ? BlockPlacements[(shapeId - 3) / 2] : BallPlacements[shapeId - 7];
  glm::mat4 shape = shapeId >= 7 ? glm::scale(glm::translate(glm::mat4(1.f), BallCenter), Vec3(BallRadius))
                    : shapeId % 2 ? BoxInObject : RectInObject;
  glm::mat4 absPlacement, absShape;
  for (int c = 0; c < 4; ++c) absPlacement[c] = glm::abs(placement[c]), absShape[c] = glm::abs(shape[c]);
  Vec3 v(glm::inverse(placement * shape) * glm::vec4(p, 1));
  return gamma(9) * Vec3(absPlacement * (absShape * glm::vec4(glm::abs(v), 1)));
}

// Both files name three materials, and the loader adds its default one.
int materialIndex(const Scene& scene, const Material* m) {
  for (int i = 0; i < 4; ++i)
    if (&scene.material(i) == m) return i;
  return -1;
}

// Rays from all around towards the objects: both scenes agree on every hit.
// The surfaces agree within both points' error bounds and the rounding by
// which the flattened vertices differ (flatteningRounding); normals and
// uvs within float rounding of unit vectors and of [0, 1] (1e-4).
TEST(Instancing, InstancesHitWhereTheFlattenedShapesDo) {
  SceneFile inst = loadSceneFromString(instancedScene(), "instanced.yaml");
  SceneFile flat = loadSceneFromString(flattenedScene(), "flattened.yaml");
  EXPECT_EQ(inst.scene->instanceCount(), 4u);
  Pcg32 rng(7, 1);
  int hits = 0, instancedHits = 0, mirroredHits = 0;
  for (int i = 0; i < 20000; ++i) {
    Vec3 target = Vec3(3.f * rng.next1D() - 1.5f, 3.f * rng.next1D() - 1.5f, 3.f * rng.next1D() - 1.5f);
    Vec3 origin = target + 6.f * randomDirection(rng);
    Ray ray{origin, glm::normalize(target - origin), Infinity};
    SurfaceInteraction a, b;
    bool hitA = inst.scene->intersect(ray, a), hitB = flat.scene->intersect(ray, b);
    ASSERT_EQ(hitA, hitB) << "ray " << i;
    if (!hitA) continue;
    ++hits;
    instancedHits += a.shapeId >= 3;
    // Both points lie on the same ray: they part along it by their surfaces'
    // separation over cos θ, so the separation is what is bounded.
    Vec3 reach = a.pError + b.pError + flatteningRounding(a.shapeId, a.p);
    ASSERT_LE(std::abs(glm::dot(a.p - b.p, a.ng)), glm::dot(glm::abs(a.ng), reach)) << "ray " << i;
    ASSERT_NEAR(glm::dot(a.ng, b.ng), 1.f, 1e-4f) << "ray " << i << ": the instance's side differs";
    ASSERT_NEAR(glm::dot(a.shading.n, b.shading.n), 1.f, 1e-4f) << "ray " << i;
    ASSERT_NEAR(a.uv.x, b.uv.x, 1e-4f) << "ray " << i;
    ASSERT_NEAR(a.uv.y, b.uv.y, 1e-4f) << "ray " << i;
    ASSERT_EQ(materialIndex(*inst.scene, a.material), materialIndex(*flat.scene, b.material)) << "ray " << i;
    EXPECT_EQ(a.emitter == nullptr, b.emitter == nullptr);
    // A ray leaving the instanced hit never finds its own triangle again.
    Vec3 out = glm::reflect(ray.d, a.ng);
    SurfaceInteraction next;
    if (inst.scene->intersect(a.spawnRay(out), next)) {
      ASSERT_FALSE(next.shapeId == a.shapeId && next.primId == a.primId && next.t < 1e-3f) << "ray " << i;
    }
    // The mirrored placement's box is hit (its sides keep the flattened mesh's winding rule).
    mirroredHits += a.shapeId == 5 || a.shapeId == 6;
  }
  EXPECT_GT(instancedHits, 2000);
  EXPECT_GT(mirroredHits, 200);
  std::cerr << hits << " hits, " << instancedHits << " on instances\n";
}

// A unit sphere under the instance scale (2, 1, 0.5) is the ellipsoid
// x²/4 + y² + 4z² = 1: rays towards its centre hit it at the analytic
// distance, with the analytic normal (the gradient (x/4, y, 4z)).
TEST(Instancing, ASphereUnderANonUniformScaleIsTheExactEllipsoid) {
  SceneFile f = loadSceneFromString(
      "camera: {position: [0, 0, 5], look_at: [0, 0, 0]}\n"
      "objects: {ball: [{type: sphere, radius: 1}]}\n"
      "shapes: [{type: instance, object: ball, transform: {scale: [2, 1, 0.5], translate: [1, 2, 3]}}]\n",
      "ellipsoid.yaml");
  Pcg32 rng(3, 5);
  const Vec3 center(1, 2, 3);
  for (int i = 0; i < 2000; ++i) {
    Vec3 origin = center + 10.f * randomDirection(rng);
    Vec3 d = glm::normalize(center - origin);
    SurfaceInteraction si;
    ASSERT_TRUE(f.scene->intersect(Ray{origin, d, Infinity}, si));
    // Solve |S⁻¹(o + t d − c)|² = 1 in double for the nearer root.
    glm::dvec3 inv(0.5, 1, 2), o = (glm::dvec3(origin) - glm::dvec3(center)) * inv, dd = glm::dvec3(d) * inv;
    double a = glm::dot(dd, dd), b = 2 * glm::dot(o, dd), c = glm::dot(o, o) - 1;
    double t = (-b - std::sqrt(b * b - 4 * a * c)) / (2 * a);
    glm::dvec3 p = glm::dvec3(origin) + t * glm::dvec3(d);
    for (int k = 0; k < 3; ++k) ASSERT_NEAR(si.p[k], p[k], si.pError[k] + 1e-6 * std::abs(p[k])) << "ray " << i;
    glm::dvec3 local = p - glm::dvec3(center);
    Vec3 n(glm::normalize(local * glm::dvec3(0.25, 1, 4)));
    ASSERT_NEAR(glm::dot(si.ng, n), 1.f, 1e-4f) << "ray " << i;
  }
}

// The instanced and the flattened scene render alike (path tracing, other
// seeds, z-tests on 4×4 regions with the films' variance).
TEST(Instancing, InstancedAndFlattenedScenesRenderAlike) {
  test::RenderSpec spec;
  spec.spp = 256;
  spec.seed = 11;
  std::string failures = test::compareScenes(loadSceneFromString(instancedScene(), "instanced.yaml"),
                                             loadSceneFromString(flattenedScene(), "flattened.yaml"), spec);
  EXPECT_TRUE(failures.empty()) << failures;
}

// The instanced scene with a masked leaf in an object, placed twice.
std::string leafyScene() {
  std::string s = instancedScene();
  s.replace(s.find("materials:\n"), std::string("materials:\n").size(),
            "materials:\n  leaf: {type: diffuse, albedo: [0.3, 0.6, 0.2], opacity: {type: checkerboard, color0: 0, color1: 1,"
            " uv_transform: [3, 0, 0, 0, 3, 0]}}\n");
  s.replace(s.find("  ball:\n"), std::string("  ball:\n").size(),
            "  leafy:\n    - {type: rectangle, material: leaf, transform: {scale: 0.8, rotate_x: -70}}\n  ball:\n");
  s += "  - {type: instance, object: leafy, transform: {translate: [0, 1.9, 0.4]}}\n"
       "  - {type: instance, object: leafy, transform: {rotate_y: 90, translate: [-0.3, 1.7, 0.6]}}\n";
  return s;
}

// Path tracing and BDPT agree on the instanced scene with a masked leaf in
// an object: light subpaths, connections and shadow rays see the instances'
// geometry and masks as camera paths do.
TEST(Instancing, PathAndBdptAgreeThroughInstancesWithAMask) {
  std::string s = leafyScene();
  std::string failures = test::pathBdptDisagreement(loadSceneFromString(s, "leafy.yaml"), 256, 1e-3, 6);
  EXPECT_TRUE(failures.empty()) << failures;
}

// Same seed, same image, bit for bit, with one and two threads, through
// instances, opacity masks (a hash of the ray, core/textures/surface_maps.h)
// and a layered BSDF (hash-seeded random walks, core/bsdfs/layered.h).
TEST(Instancing, MasksLayeredBsdfsAndInstancesAreBitIdenticalWithOneAndTwoThreads) {
  std::string s = leafyScene();
  s.replace(s.find("  shiny: {type: conductor, roughness: 0.2}"), std::string("  shiny: {type: conductor, roughness: 0.2}").size(),
            "  shiny: {type: coated_diffuse, roughness: 0.3, albedo: [0.6, 0.3, 0.2]}");
  SceneFile sf = loadSceneFromString(s, "leafy.yaml");
  for (std::string integrator : {"path", "bdpt"}) {
    Image one = test::renderScene(sf, {integrator, "{}", 4, 42, 1})->image();
    Image two = test::renderScene(sf, {integrator, "{}", 4, 42, 2})->image();
    EXPECT_EQ(std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(Color)), 0) << integrator;
  }
}

// What a file may not do with objects: one line naming file, line and key.
TEST(Instancing, BadObjectsAndInstancesAreOneErrorNamingTheKey) {
  const std::string head = "camera: {position: [0, 0, 5], look_at: [0, 0, 0]}\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"objects: {ball: [{type: sphere}]}\nshapes: [{type: instance, object: bal}]\n",
       "'shapes[0].object': unknown object 'bal'; did you mean 'ball'?"},
      {"objects: {lamp: [{type: sphere, emission: 1}]}\n", "'objects.lamp[0].emission': an object's shapes cannot emit"},
      {"objects: {a: [{type: sphere}], b: [{type: instance, object: a}]}\n", "'objects.b[0].type': an object cannot hold instances"},
      {"objects: {a: []}\n", "'objects.a': expected a list of shapes"},
      {"objects: {ball: [{type: sphere}]}\nshapes: [{type: instance, object: ball, material: m}]\n",
       "'shapes[0].material': unknown key"},
      {"objects: {ball: [{type: sphere}]}\nshapes: [{type: instance, object: ball, transform: {translate: [2e17, 0, 0]}}]\n",
       "'shapes[0].transform': lies beyond"},
  };
  for (const auto& [body, expected] : cases) {
    try {
      loadSceneFromString(head + body, "bad.yaml");
      ADD_FAILURE() << "accepted:\n" << body;
    } catch (const ConfigError& e) {
      std::string what = e.what();
      EXPECT_NE(what.find(expected), std::string::npos) << what;
      EXPECT_EQ(what.rfind("bad.yaml:", 0), 0u) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
}

}  // namespace
}  // namespace lb
