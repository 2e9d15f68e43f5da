// Geometry at the extremes (issue 7): rays aimed exactly at the shared edges
// and vertices of a closed mesh never leak through it, rays starting exactly
// on an edge or a vertex do not hit their own surface, and zero-area triangles
// are dropped with a warning; a face on a coordinate plane is lit; the ray
// offsets' float stepping is std::nextafter.
#include <gtest/gtest.h>
#include <filesystem>
#include <fstream>
#include <cstring>
#include <xmmintrin.h>
#include "core/rng.h"
#include "core/scene.h"
#include "core/scene_loader.h"
#include "tests/support/render_helpers.h"

namespace lb {
namespace {

// A closed cube [-1, 1]³ seen from inside (a `box` shape: 12 triangles
// sharing its 12 edges and 8 vertices).
const char* const CubeScene = R"(
camera: {position: [0, 0, 0.5], look_at: [0, 0, 0], fov: 60}
film: {width: 4, height: 4}
materials: {m: {type: diffuse}}
shapes: [{type: box, material: m}]
)";

std::vector<Vec3> edgeAndVertexPoints() {
  std::vector<Vec3> points;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z) {
        int onFaces = (x != 0) + (y != 0) + (z != 0);
        if (onFaces >= 2) points.push_back(Vec3(x, y, z));  // 12 edge midpoints and 8 vertices
      }
  // Points along the face diagonals, where the two triangles of a face meet.
  for (float t : {-0.7f, -0.3f, 0.1f, 0.6f}) points.push_back(Vec3(t, t, 1)), points.push_back(Vec3(1, t, -t));
  return points;
}

TEST(GeometryExtremes, RaysAtSharedEdgesAndVerticesNeverLeak) {
  SceneFile sf = loadSceneFromString(CubeScene, "cube.yaml");
  for (Vec3 origin : {Vec3(0.f), Vec3(0.3f, -0.2f, 0.1f), Vec3(-0.9f, 0.95f, 0.5f)})
    for (const Vec3& target : edgeAndVertexPoints()) {
      Vec3 d = glm::normalize(target - origin);
      SurfaceInteraction si;
      ASSERT_TRUE(sf.scene->intersect(Ray{origin, d, Infinity}, si)) << "leak towards " << target.x << "," << target.y << "," << target.z;
      // It hits the cube where it should: at the target (or, from a corner-near
      // origin, no farther than it).
      EXPECT_LE(si.t, glm::length(target - origin) * (1 + 1e-5f));
    }
}

// A ray leaving a point exactly on an edge or vertex is offset from the
// triangle it hit (pbrt-v4's error bounds), but the neighbouring face passes
// within the point's float error too: the ray may touch it at once, within
// that error, and must then go on across the cube from there. Either way it
// never re-hits its own triangle and never gets stuck.
TEST(GeometryExtremes, RaysStartingOnEdgesAndVerticesLeaveTheSurface) {
  SceneFile sf = loadSceneFromString(CubeScene, "cube.yaml");
  int touchedNeighbour = 0, total = 0;
  for (const Vec3& target : edgeAndVertexPoints()) {
    SurfaceInteraction at;
    ASSERT_TRUE(sf.scene->intersect(Ray{Vec3(0.f), glm::normalize(target), Infinity}, at));
    for (const Vec3& across : {Vec3(0.f), -target * 0.9f, Vec3(target.y, -target.x, -target.z) * 0.5f}) {
      Vec3 d = glm::normalize(across - at.p);
      ++total;
      // At a vertex three faces meet: at most two neighbours can be touched.
      SurfaceInteraction from = at, next;
      bool crossed = false;
      for (int step = 0; step < 3 && !crossed; ++step) {
        ASSERT_TRUE(sf.scene->intersect(from.spawnRay(d), next));
        if (next.t > 0.5f) {
          crossed = true;
          break;
        }
        touchedNeighbour += step == 0;
        EXPECT_FALSE(next.shapeId == from.shapeId && next.primId == from.primId) << "re-hit its own triangle";
        // Within the float error of the two points: the distance along the
        // neighbour's normal is at most both ends' error boxes plus the spawn
        // offset (itself at most one error box), so 3 error reaches; 4 leaves
        // room for the offset's rounding away from the surface.
        float errorReach = glm::length(from.pError) + glm::length(next.pError);
        EXPECT_LE(next.t * absDot(d, next.ng), 4 * errorReach) << "a real hit, not float error";
        from = next;
      }
      EXPECT_TRUE(crossed) << "stuck at the edge towards " << target.x << "," << target.y << "," << target.z;
    }
  }
  std::cerr << touchedNeighbour << " of " << total << " rays from edges and vertices touched the neighbouring face first\n";
}

TEST(GeometryExtremes, ZeroAreaTrianglesAreSkippedWithAWarning) {
  auto dir = std::filesystem::temp_directory_path() / "lightbench-degenerate";
  std::filesystem::create_directories(dir);
  // One good triangle, one with collinear vertices, one with two vertices at the same position.
  std::ofstream(dir / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nv 1 0 0\n"
                                    "f 1 2 3\nf 1 2 4\nf 2 5 3\n";
  std::string scene = "camera: {position: [0.2, 0.2, 2], look_at: [0.2, 0.2, 0], fov: 30}\n"
                      "film: {width: 4, height: 4}\n"
                      "shapes: [{type: mesh, file: tri.obj}]\n";
  std::ofstream(dir / "scene.yaml") << scene;
  ::testing::internal::CaptureStderr();
  SceneFile sf = loadScene((dir / "scene.yaml").string());
  std::string warnings = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(sf.degenerateTriangles, 2u);
  EXPECT_NE(warnings.find("degenerate"), std::string::npos) << warnings;
  SurfaceInteraction si;
  EXPECT_TRUE(sf.scene->intersect(Ray{Vec3(0.2f, 0.2f, 2), Vec3(0, 0, -1), Infinity}, si));  // the good one stays
  std::filesystem::remove_all(dir);
}

// A mesh face lying exactly on a coordinate plane: a slab whose top is at
// y = 0 exactly (0.1·1 − 0.1 in float). Its vertices' y are all 0, so the
// per-component barycentric error bound across the face was 0, rays started
// on the plane and Embree found the face again: every shadow ray was
// blocked and the lit floor rendered black (mean 0 against 0.301). It must
// give the analytic point light over a plane.
TEST(GeometryExtremes, AFaceOnACoordinatePlaneIsLit) {
  std::string scene = test::PointLightPlaneScene;
  std::string plane = "{type: rectangle, material: m, transform: {scale: 10, rotate_x: -90}}";
  scene.replace(scene.find(plane), plane.size(), "{type: box, material: m, transform: {scale: [10, 0.1, 10], translate: [0, -0.1, 0]}}");
  SceneFile sf = loadSceneFromString(scene, "slab.yaml");
  auto film = test::renderScene(sf, {"path", "{max_depth: 2}", 64, 7});
  EXPECT_TRUE(test::meanMatches(*film, test::pointLightOverPlane(sf.scene->camera, Vec3(0.3f, 2, 0.2f), 10, 0.5f), 0.01));
}

}  // namespace
}  // namespace lb

namespace lb {
namespace {

// Ray offsets step p to its neighbouring float (core/ray.h). The inline
// nextFloatUp/Down (core/math.h) must be std::nextafter towards ±∞ on every
// class of float: zeros of both signs, denormals, the largest finite values,
// infinities, NaN, and random bit patterns of both signs; with denormals
// flushed to zero too, as the renderers run (a first version compared floats
// and differed there on denormals).

TEST(GeometryExtremes, NextFloatIsStdNextafter) {
  auto same = [](float a, float b) {
    uint32_t x, y;
    std::memcpy(&x, &a, 4), std::memcpy(&y, &b, 4);
    return (std::isnan(a) && std::isnan(b)) || x == y;
  };
  std::vector<float> values = {0.f, -0.f, std::numeric_limits<float>::denorm_min(),
                               -std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::min(),
                               -std::numeric_limits<float>::min(), std::numeric_limits<float>::max(),
                               -std::numeric_limits<float>::max(), Infinity, -Infinity,
                               std::numeric_limits<float>::quiet_NaN(), 1.f, -1.f};
  Pcg32 rng(3, 5);
  for (int i = 0; i < 100000; ++i) {
    uint32_t bits = rng.nextU32();
    float v;
    std::memcpy(&v, &bits, 4);
    values.push_back(v);
  }
  auto wrong = [&] {
    int n = 0;
    for (float v : values) {
      n += !same(nextFloatUp(v), std::nextafter(v, Infinity));
      n += !same(nextFloatDown(v), std::nextafter(v, -Infinity));
    }
    return n;
  };
  unsigned csr = _mm_getcsr();
  _mm_setcsr(csr & ~0x8040u);  // denormals as they are
  EXPECT_EQ(wrong(), 0);
  enableFlushToZero();
  EXPECT_EQ(wrong(), 0) << "with flush-to-zero";
  _mm_setcsr(csr);
}

}  // namespace
}  // namespace lb
