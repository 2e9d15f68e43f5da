// Per-group materials on one mesh (issue 14): an OBJ's usemtl groups given
// their own materials by `materials: {group: material}`, checked by which
// material a ray meets on each face, and the errors around it.
#include <gtest/gtest.h>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include "core/error.h"
#include "core/scene_loader.h"

namespace lb {
namespace {

// Three faces side by side along x at z = 0: a triangle before any usemtl,
// a quad in group "red" (two triangles), a triangle in group "blue".
const char* kObj =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
    "v 2 0 0\nv 3 0 0\nv 3 1 0\nv 2 1 0\n"
    "v 4 0 0\nv 5 0 0\nv 4 1 0\n"
    "f 1 2 3\n"
    "usemtl red\nf 4 5 6 7\n"
    "usemtl blue\nf 8 9 10\n";

class MeshMaterials : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("lb-groups-" + std::to_string(getpid()));
    std::filesystem::create_directories(dir_);
    std::ofstream(dir_ / "groups.obj") << kObj;
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  SceneFile load(const std::string& shapeKeys) {
    std::string yaml =
        "camera: {position: [2.5, 0.5, 5], look_at: [2.5, 0.5, 0]}\n"
        "materials:\n  grey: {type: diffuse, albedo: 0.5}\n  r: {type: diffuse, albedo: [0.9, 0, 0]}\n"
        "  b: {type: diffuse, albedo: [0, 0, 0.9]}\n"
        "shapes:\n  - {type: mesh, file: groups.obj, " + shapeKeys + "}\n";
    return loadSceneFromString(yaml, (dir_ / "scene.yaml").string());
  }
  // The material a ray straight down -z meets at x.
  const Material* materialAt(const SceneFile& f, float x) {
    SurfaceInteraction si;
    EXPECT_TRUE(f.scene->intersect(Ray{Vec3(x, 0.25f, 1), Vec3(0, 0, -1), Infinity}, si)) << x;
    return si.material;
  }
  std::filesystem::path dir_;
};

TEST_F(MeshMaterials, EachGroupHasItsMaterialAndTheRestTheShapes) {
  SceneFile f = load("material: grey, materials: {red: r, blue: b}");
  const Material* first = materialAt(f, 0.25f);
  const Material* quadLeft = materialAt(f, 2.2f);   // the quad's two triangles
  const Material* quadRight = materialAt(f, 2.9f);
  const Material* last = materialAt(f, 4.25f);
  EXPECT_EQ(quadLeft, quadRight);
  EXPECT_NE(first, quadLeft);
  EXPECT_NE(last, quadLeft);
  EXPECT_NE(first, last);
  // Told apart by their albedo: red reflects red only, blue blue only.
  BSDFEval red = quadLeft->eval(Vec3(0, 0, 1), Vec3(0, 0, 1), TransportMode::Radiance);
  BSDFEval blue = last->eval(Vec3(0, 0, 1), Vec3(0, 0, 1), TransportMode::Radiance);
  EXPECT_GT(red.f.r, 0.f);
  EXPECT_EQ(red.f.b, 0.f);
  EXPECT_GT(blue.f.b, 0.f);
  EXPECT_EQ(blue.f.r, 0.f);
  EXPECT_NEAR(first->eval(Vec3(0, 0, 1), Vec3(0, 0, 1), TransportMode::Radiance).f.g, 0.5f / Pi, 1e-6);
}

TEST_F(MeshMaterials, DroppedDegenerateTrianglesKeepTheGroupsInStep) {
  // A zero-area face first (dropped after loading) must not shift the others.
  SceneFile f = [&] {
    std::ofstream out(dir_ / "groups.obj");
    out << "v 7 0 0\nv 8 0 0\nv 9 0 0\nusemtl flat\nf 1 2 3\n";
    // kObj's vertex indices moved by the three new vertices.
    out << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nv 3 0 0\nv 3 1 0\nv 2 1 0\nv 4 0 0\nv 5 0 0\nv 4 1 0\n"
           "usemtl none\nf 4 5 6\nusemtl red\nf 7 8 9 10\nusemtl blue\nf 11 12 13\n";
    out.close();
    return load("material: grey, materials: {red: r, blue: b}");
  }();
  const Material* quad = materialAt(f, 2.5f);
  const Material* last = materialAt(f, 4.25f);
  EXPECT_GT(quad->eval(Vec3(0, 0, 1), Vec3(0, 0, 1), TransportMode::Radiance).f.r, 0.f);
  EXPECT_EQ(quad->eval(Vec3(0, 0, 1), Vec3(0, 0, 1), TransportMode::Radiance).f.b, 0.f);
  EXPECT_GT(last->eval(Vec3(0, 0, 1), Vec3(0, 0, 1), TransportMode::Radiance).f.b, 0.f);
}

TEST_F(MeshMaterials, UnknownGroupsAndMaterialsAreErrorsWithAHint) {
  try {
    load("materials: {rde: r}");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'red'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load("materials: {red: nosuch}"), ConfigError);
}

TEST_F(MeshMaterials, AFileWithoutGroupsOrWithRefusedFacesSaysSo) {
  std::ofstream(dir_ / "groups.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  EXPECT_THROW(load("materials: {red: r}"), ConfigError);
  // A face OpenMesh refuses (a repeated vertex) would shift every later
  // face's group: refused, not guessed.
  std::ofstream(dir_ / "groups.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nusemtl a\nf 1 1 2\nusemtl red\nf 2 4 3\n";
  try {
    load("materials: {red: r}");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot be matched"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace lb
