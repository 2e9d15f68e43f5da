// How the Mitsuba importer resolves BSDFs as Bitterli's scenes write them
// (issue 35): a <ref> to a BSDF defined further down the file, BSDFs wrapped
// in a bump map, normal map or opacity mask (not modelled yet: said once, the
// wrapped BSDF used, its id resolving), and a conductor's ext_eta.
#include <gtest/gtest.h>
#include "core/error.h"
#include "tests/support/mitsuba_snippets.h"

namespace lb {
namespace {

using test::xmlScene;

MitsubaImport import(const std::string& xml) { return test::importSnippet(xml); }

std::string allWarnings(const MitsubaImport& imp) {
  std::string all;
  for (const ImportWarning& w : imp.warnings) all += w.text("test") + "\n";
  return all;
}

TEST(MitsubaReferences, ARefMayNameABsdfDefinedFurtherDown) {
  MitsubaImport imp = import(xmlScene(
      "<shape type=\"sphere\"><ref id=\"late\"/></shape>\n"
      "<bsdf type=\"diffuse\" id=\"late\"><rgb name=\"reflectance\" value=\"0.2, 0.4, 0.6\"/></bsdf>\n"));
  ASSERT_EQ(imp.scene["shapes"].size(), 1u);
  std::string material = imp.scene["shapes"][0]["material"].as<std::string>();
  EXPECT_EQ(material, "late");
  EXPECT_EQ(imp.scene["materials"][material]["albedo"][2].as<double>(), 0.6);
  // An id that is nowhere is still an error at the ref's line.
  try {
    import(xmlScene("<shape type=\"sphere\">\n<ref id=\"nowhere\"/></shape>\n"));
    FAIL() << "a ref to no BSDF was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("test.xml:5:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no BSDF with id 'nowhere' in the scene"), std::string::npos) << e.what();
  }
}

// As staircase writes its brushed aluminium: a bump map without an id around
// a twosided BSDF with one, which shapes refer to. Mitsuba's <ref> to the
// nested id gets the nested BSDF alone: no bump map; the wrapper's own id
// (the mask's) gets the map.
TEST(MitsubaReferences, AWrapperAddsItsMapAndANestedIdNamesTheBsdfWithout) {
  MitsubaImport imp = import(xmlScene(
      "<bsdf type=\"bumpmap\">\n"
      "  <texture type=\"bitmap\"><string name=\"filename\" value=\"bump.png\"/></texture>\n"
      "  <bsdf type=\"twosided\" id=\"Brushed\">\n"
      "    <bsdf type=\"roughconductor\"><float name=\"alpha\" value=\"0.2\"/></bsdf>\n"
      "  </bsdf>\n"
      "</bsdf>\n"
      "<bsdf type=\"mask\" id=\"Leaf\"><float name=\"opacity\" value=\"0.25\"/>\n"
      "  <bsdf type=\"diffuse\" id=\"LeafInside\"/></bsdf>\n"
      "<shape type=\"sphere\"><ref id=\"Brushed\"/></shape>\n"
      "<shape type=\"sphere\"><ref id=\"Leaf\"/></shape>\n"
      "<shape type=\"sphere\"><ref id=\"LeafInside\"/></shape>\n"));
  ASSERT_EQ(imp.scene["shapes"].size(), 3u);
  const YAML::Node& materials = imp.scene["materials"];
  const YAML::Node brushed = materials[imp.scene["shapes"][0]["material"].as<std::string>()];
  EXPECT_EQ(brushed["type"].as<std::string>(), "conductor");
  EXPECT_EQ(brushed["roughness"].as<double>(), 0.2);
  EXPECT_FALSE(brushed["bump_map"]) << "a ref to the nested id is not bumped";
  int bumped = 0;
  for (const auto& kv : materials)
    if (kv.second["bump_map"]) {
      ++bumped;
      EXPECT_EQ(kv.second["bump_map"]["file"].as<std::string>(), "bump.png");
      EXPECT_EQ(kv.second["roughness"].as<double>(), 0.2) << "the wrapper copies the material it wraps";
    }
  EXPECT_EQ(bumped, 1);
  const YAML::Node leaf = materials[imp.scene["shapes"][1]["material"].as<std::string>()];
  const YAML::Node inside = materials[imp.scene["shapes"][2]["material"].as<std::string>()];
  EXPECT_EQ(leaf["opacity"].as<double>(), 0.25);
  EXPECT_FALSE(inside["opacity"]);
  EXPECT_EQ(inside["type"].as<std::string>(), "diffuse");
  std::string all = allWarnings(imp);
  EXPECT_EQ(all.find("bumpmap"), std::string::npos) << all;
  EXPECT_EQ(all.find("mask"), std::string::npos) << all;
  EXPECT_EQ(all.find("twosided"), std::string::npos) << all;  // the twosided inside the bump map is read
  EXPECT_EQ(all.find("not supported yet; approximated as diffuse"), std::string::npos) << all;
}

// Mitsuba 3's normalmap (its texture named normalmap), bumpmap with a scale,
// and a mask whose opacity is a texture, nested in a twosided BSDF as
// living-room writes its leaves (the only reflecting BSDF here, so no
// one-sided warning).
TEST(MitsubaReferences, NormalMapsScaledBumpMapsAndTexturedMasksImport) {
  MitsubaImport imp = import(xmlScene(
      "<bsdf type=\"normalmap\" id=\"n\">\n"
      "  <texture name=\"normalmap\" type=\"bitmap\"><string name=\"filename\" value=\"n.png\"/>"
      "<boolean name=\"raw\" value=\"true\"/></texture>\n"
      "  <bsdf type=\"dielectric\"/>\n"
      "</bsdf>\n"
      "<bsdf type=\"bumpmap\" id=\"b\"><float name=\"scale\" value=\"0.3\"/>\n"
      "  <texture name=\"arbitrary\" type=\"bitmap\"><string name=\"filename\" value=\"h.png\"/></texture>\n"
      "  <bsdf type=\"dielectric\"/>\n"
      "</bsdf>\n"
      "<bsdf type=\"twosided\" id=\"leaves\"><bsdf type=\"mask\">\n"
      "  <texture name=\"opacity\" type=\"bitmap\"><string name=\"filename\" value=\"leaf.png\"/></texture>\n"
      "  <bsdf type=\"diffuse\"/>\n"
      "</bsdf></bsdf>\n"
      "<shape type=\"rectangle\"><ref id=\"n\"/></shape>\n"
      "<shape type=\"rectangle\"><ref id=\"b\"/></shape>\n"
      "<shape type=\"rectangle\"><ref id=\"leaves\"/></shape>\n"));
  const YAML::Node& materials = imp.scene["materials"];
  auto of = [&](int shape) { return materials[imp.scene["shapes"][shape]["material"].as<std::string>()]; };
  EXPECT_EQ(of(0)["normal_map"]["file"].as<std::string>(), "n.png");
  EXPECT_FALSE(of(0)["normal_map"]["srgb"].as<bool>()) << "raw: read as linear values";
  EXPECT_EQ(of(1)["bump_map"]["file"].as<std::string>(), "h.png");
  EXPECT_EQ(of(1)["bump_scale"].as<double>(), 0.3);
  EXPECT_EQ(of(2)["opacity"]["file"].as<std::string>(), "leaf.png");
  EXPECT_EQ(of(2)["type"].as<std::string>(), "diffuse");
  std::string all = allWarnings(imp);
  EXPECT_EQ(all.find("one-sided"), std::string::npos) << "the mask's diffuse is inside a twosided BSDF: " << all;
}

// A <ref> may name a wrapper's BSDF; a normal map around a bump map keeps the
// outer (lightbench takes one); an anonymous nested BSDF leaves no material
// of its own behind.
TEST(MitsubaReferences, WrappersTakeARefAndKeepOneShadingMap) {
  MitsubaImport imp = import(xmlScene(
      "<bsdf type=\"dielectric\" id=\"glass\"/>\n"
      "<bsdf type=\"bumpmap\" id=\"bumpy\">\n"
      "  <texture type=\"bitmap\"><string name=\"filename\" value=\"h.png\"/></texture>\n"
      "  <ref id=\"glass\"/>\n"
      "</bsdf>\n"
      "<bsdf type=\"normalmap\" id=\"both\">\n"
      "  <texture name=\"normalmap\" type=\"bitmap\"><string name=\"filename\" value=\"n.png\"/></texture>\n"
      "  <bsdf type=\"bumpmap\"><texture type=\"bitmap\"><string name=\"filename\" value=\"h.png\"/></texture>\n"
      "    <bsdf type=\"dielectric\"/></bsdf>\n"
      "</bsdf>\n"
      "<shape type=\"rectangle\"><ref id=\"bumpy\"/></shape>\n"
      "<shape type=\"rectangle\"><ref id=\"both\"/></shape>\n"));
  const YAML::Node& materials = imp.scene["materials"];
  auto of = [&](int shape) { return materials[imp.scene["shapes"][shape]["material"].as<std::string>()]; };
  EXPECT_EQ(of(0)["type"].as<std::string>(), "dielectric");
  EXPECT_EQ(of(0)["bump_map"]["file"].as<std::string>(), "h.png");
  EXPECT_EQ(of(1)["normal_map"]["file"].as<std::string>(), "n.png");
  EXPECT_FALSE(of(1)["bump_map"]);
  EXPECT_NE(allWarnings(imp).find("only the outer map is applied"), std::string::npos) << allWarnings(imp);
  EXPECT_EQ(materials.size(), 3u) << "glass, bumpy and both; no anonymous leftovers";
}

// Mitsuba 0.6's conductor divides eta and k by the exterior's index.
TEST(MitsubaReferences, ExtEtaDividesTheConductorsIndices) {
  MitsubaImport imp = import(xmlScene(
      "<bsdf type=\"conductor\" id=\"c\"><rgb name=\"eta\" value=\"0.3, 0.6, 1.2\"/>"
      "<rgb name=\"k\" value=\"3, 2.4, 1.5\"/><float name=\"ext_eta\" value=\"1.5\"/></bsdf>\n"
      "<shape type=\"sphere\"><ref id=\"c\"/></shape>\n"));
  const YAML::Node& m = imp.scene["materials"]["c"];
  EXPECT_DOUBLE_EQ(m["eta"][0].as<double>(), 0.2);
  EXPECT_DOUBLE_EQ(m["eta"][2].as<double>(), 0.8);
  EXPECT_DOUBLE_EQ(m["k"][0].as<double>(), 2.0);
  EXPECT_DOUBLE_EQ(m["k"][2].as<double>(), 1.0);
  EXPECT_EQ(allWarnings(imp).find("ext_eta"), std::string::npos) << allWarnings(imp);
  // A named exterior (air) reads as its index.
  MitsubaImport air = import(xmlScene(
      "<bsdf type=\"conductor\" id=\"c\"><string name=\"material\" value=\"Cu\"/><string name=\"ext_eta\" value=\"air\"/></bsdf>\n"
      "<shape type=\"sphere\"><ref id=\"c\"/></shape>\n"));
  EXPECT_DOUBLE_EQ(air.scene["materials"]["c"]["eta"][0].as<double>(), 0.200438 / 1.000277);
}

}  // namespace
}  // namespace lb
