// Mitsuba's shapegroup and instance (issue 35): a shapegroup becomes an
// object of the scene (`objects:`, its shapes in the group's space) and each
// instance an `instance` shape with its to_world, placed by Embree instancing
// (core/scene.h; the geometry itself is tested in instancing_test.cpp). What
// instancing leaves out is said once, and a bad reference is one error at its
// line.
#include <gtest/gtest.h>
#include <unistd.h>
#include <filesystem>
#include <fstream>
#include "core/error.h"
#include "core/scene_loader.h"
#include "tests/support/instancing_checks.h"
#include "tests/support/mitsuba_snippets.h"

namespace lb {
namespace {

using test::importSnippet;
using test::xmlScene;

bool hasWarning(const MitsubaImport& imp, const std::string& text) {
  for (const ImportWarning& w : imp.warnings)
    if (w.message.find(text) != std::string::npos) return true;
  return false;
}

// An instance may come before its group, as a <ref> to a BSDF may.
const std::string Ball =
    "<bsdf type=\"diffuse\" id=\"white\"/>\n"
    "<shape type=\"instance\"><ref id=\"ball\"/><transform name=\"to_world\"><translate x=\"10\"/></transform></shape>\n"
    "<shape type=\"shapegroup\" id=\"ball\">\n"
    "  <shape type=\"sphere\"><point name=\"center\" x=\"0\" y=\"1\" z=\"0\"/><ref id=\"white\"/></shape>\n"
    "  <shape type=\"rectangle\"><ref id=\"white\"/><transform name=\"to_world\"><translate z=\"-3\"/></transform></shape>\n"
    "</shape>\n"
    "<shape type=\"instance\"><ref id=\"ball\"/><transform name=\"to_world\"><translate x=\"20\"/></transform></shape>\n";

TEST(MitsubaInstancing, ShapegroupsBecomeObjectsThatInstancesPlace) {
  MitsubaImport imp = importSnippet(xmlScene(Ball));
  // (The scene's own warnings, no integrator and a one-sided diffuse, are
  // not about instancing.)
  EXPECT_FALSE(hasWarning(imp, "instance") || hasWarning(imp, "shapegroup"));
  ASSERT_EQ(imp.scene["objects"]["ball"].size(), 2u);
  EXPECT_EQ(imp.scene["objects"]["ball"][0]["type"].as<std::string>(), "sphere");
  YAML::Node shapes = imp.scene["shapes"];
  ASSERT_EQ(shapes.size(), 2u);
  for (int i : {0, 1}) {
    EXPECT_EQ(shapes[i]["type"].as<std::string>(), "instance");
    EXPECT_EQ(shapes[i]["object"].as<std::string>(), "ball");
    EXPECT_DOUBLE_EQ(shapes[i]["transform"]["matrix"][3].as<double>(), 10.0 * (i + 1));  // row 0, column 3
  }

  // Loaded: the group's sphere and rectangle where each instance puts them.
  std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("lb_mitsuba_instances_" + std::to_string(::getpid()) + ".xml");
  std::ofstream(file) << xmlScene(Ball);
  SceneFile loaded = loadScene(file.string());
  std::filesystem::remove(file);
  EXPECT_EQ(loaded.scene->instanceCount(), 2u);
  SurfaceInteraction si;
  ASSERT_TRUE(loaded.scene->intersect(Ray{Vec3(20, 1, 5), Vec3(0, 0, -1), Infinity}, si));
  EXPECT_NEAR(si.p.z, 1.0f, 1e-5f);  // the unit sphere at (20, 1, 0)
  ASSERT_TRUE(loaded.scene->intersect(Ray{Vec3(10.9f, -0.9f, 5), Vec3(0, 0, -1), Infinity}, si));
  EXPECT_NEAR(si.p.z, -3.0f, 1e-5f);  // past the sphere, the rectangle at z = -3 about x = 10
}

// An emitter inside a group (instances do not emit), a mirroring instance
// (lightbench's winding rule turns its triangles over), and a group whose
// every shape was dropped, which places nothing.
TEST(MitsubaInstancing, GapsAreWarnedAndAnEmptyGroupPlacesNothing) {
  MitsubaImport imp = importSnippet(xmlScene(
      "<shape type=\"shapegroup\" id=\"lamp\">\n"
      "  <shape type=\"sphere\"><emitter type=\"area\"><rgb name=\"radiance\" value=\"1\"/></emitter></shape>\n"
      "</shape>\n"
      "<shape type=\"shapegroup\" id=\"nothing\"><shape type=\"cylinder\"/></shape>\n"
      "<shape type=\"instance\"><ref id=\"lamp\"/><transform name=\"to_world\"><scale x=\"-1\"/></transform></shape>\n"
      "<shape type=\"instance\"><ref id=\"nothing\"/></shape>\n"));
  EXPECT_TRUE(hasWarning(imp, "instances do not emit"));
  EXPECT_TRUE(hasWarning(imp, "mirroring transform"));
  test::expectLampWithoutEmissionAndNothingPlaced(imp.scene);
}

TEST(MitsubaInstancing, BadReferencesAreOneErrorAtTheirLine) {
  auto error = [](const std::string& body) {
    try {
      importSnippet(xmlScene(body));
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string group = "<shape type=\"shapegroup\" id=\"g\"><shape type=\"sphere\"/></shape>\n";
  std::string e = error(group + "<shape type=\"instance\"><ref id=\"nowhere\"/></shape>\n");
  EXPECT_NE(e.find("test.xml:5:"), std::string::npos) << e;
  EXPECT_NE(e.find("no shapegroup with id 'nowhere'"), std::string::npos) << e;
  e = error(group + "<bsdf type=\"diffuse\" id=\"white\"/>\n<shape type=\"instance\"><ref id=\"white\"/></shape>\n");
  EXPECT_NE(e.find("'white' is not a shapegroup"), std::string::npos) << e;
  e = error(group + "<shape type=\"instance\"/>\n");
  EXPECT_NE(e.find("needs a <ref> to a shapegroup"), std::string::npos) << e;
  e = error("<shape type=\"shapegroup\" id=\"h\">\n<shape type=\"instance\"><ref id=\"g\"/></shape></shape>\n" + group);
  EXPECT_NE(e.find("test.xml:5:"), std::string::npos) << e;
  EXPECT_NE(e.find("one level deep"), std::string::npos) << e;
  e = error("<shape type=\"shapegroup\"><shape type=\"sphere\"/></shape>\n");
  EXPECT_NE(e.find("test.xml:4: '<shape type=\"shapegroup\">.id': a shapegroup needs an id"), std::string::npos) << e;
}

}  // namespace
}  // namespace lb
