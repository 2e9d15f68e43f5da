// The Mitsuba importer's textures, environment maps, and the BSDFs and shapes
// added for them (core/mitsuba/textures.cpp, bsdfs.cpp, import.cpp): what each
// element becomes, values worked out by hand from Mitsuba's definitions.
#include <gtest/gtest.h>
#include <cmath>
#include "core/error.h"
#include "core/mitsuba/import.h"
#include "tests/support/mitsuba_snippets.h"

namespace lb {
namespace {

using test::xmlScene;
MitsubaImport import(const std::string& xml) { return test::importSnippet(xml); }
bool warned(const MitsubaImport& imp, const std::string& phrase) {
  for (const ImportWarning& w : imp.warnings)
    if ((w.element + w.message).find(phrase) != std::string::npos) return true;
  return false;
}
std::vector<double> numbers(const YAML::Node& seq) {
  std::vector<double> v;
  for (const auto& x : seq) v.push_back(x.as<double>());
  return v;
}

TEST(MitsubaTextures, BitmapBecomesAnImageTextureOnTheAlbedo) {
  MitsubaImport imp = import(xmlScene(
      "<bsdf type=\"diffuse\" id=\"wood\"><texture type=\"bitmap\" name=\"reflectance\">"
      "<string name=\"filename\" value=\"maps/wood.png\"/><boolean name=\"raw\" value=\"true\"/>"
      "<string name=\"filter_type\" value=\"nearest\"/>"
      "<transform name=\"to_uv\"><scale x=\"2\" y=\"3\"/><translate x=\"0.5\" y=\"0.25\"/></transform>"
      "</texture></bsdf>\n"));
  YAML::Node m = imp.scene["materials"]["wood"];
  EXPECT_EQ(m["type"].as<std::string>(), "diffuse");
  EXPECT_EQ(m["albedo"].as<double>(), 1.0);  // the texture is the whole colour
  YAML::Node t = m["texture"];
  EXPECT_EQ(t["type"].as<std::string>(), "image");
  EXPECT_EQ(t["file"].as<std::string>(), "maps/wood.png");
  EXPECT_FALSE(t["srgb"].as<bool>());
  EXPECT_EQ(t["filter"].as<std::string>(), "nearest");
  // Scale, then translate: u' = 2u + 0.5, v' = 3v + 0.25.
  EXPECT_EQ(numbers(t["uv_transform"]), (std::vector<double>{2, 0, 0.5, 0, 3, 0.25}));
}

TEST(MitsubaTextures, OldDialectScalesAndOffsetsAndMipMappingIsApproximated) {
  MitsubaImport imp = import(xmlScene(
      "<bsdf type=\"diffuse\" id=\"d\"><texture type=\"bitmap\" name=\"diffuseReflectance\">"
      "<string name=\"filename\" value=\"a.png\"/><float name=\"uscale\" value=\"4\"/><float name=\"voffset\" value=\"0.5\"/>"
      "<float name=\"gamma\" value=\"1\"/></texture></bsdf>\n", "0.5.0"));
  YAML::Node t = imp.scene["materials"]["d"]["texture"];
  EXPECT_EQ(numbers(t["uv_transform"]), (std::vector<double>{4, 0, 0, 0, 1, 0.5}));
  EXPECT_FALSE(t["srgb"].as<bool>());  // gamma 1: linear values
  EXPECT_TRUE(warned(imp, "filter_type 'ewa'"));  // 0.x's default filter
}

TEST(MitsubaTextures, CheckerboardByReferenceTintsAConductor) {
  MitsubaImport imp = import(xmlScene(
      "<texture type=\"checkerboard\" id=\"checks\"><rgb name=\"color0\" value=\"0.9, 0.5, 0.1\"/></texture>\n"
      "<bsdf type=\"conductor\" id=\"c\"><ref name=\"specular_reflectance\" id=\"checks\"/></bsdf>\n"));
  YAML::Node m = imp.scene["materials"]["c"];
  EXPECT_EQ(m["tint"].as<double>(), 1.0);
  YAML::Node t = m["texture"];
  EXPECT_EQ(t["type"].as<std::string>(), "checkerboard");
  EXPECT_EQ(numbers(t["color0"]), (std::vector<double>{0.9, 0.5, 0.1}));
  EXPECT_EQ(numbers(t["color1"]), (std::vector<double>{0.2, 0.2, 0.2}));  // Mitsuba's default
  EXPECT_TRUE(imp.warnings.empty() || !warned(imp, "texture"));
}

TEST(MitsubaTextures, UnsupportedTexturesAndTargetsAreWarnedAndDropped) {
  MitsubaImport imp = import(xmlScene(
      "<bsdf type=\"roughconductor\" id=\"r\"><texture type=\"checkerboard\" name=\"alpha\"/></bsdf>\n"
      "<bsdf type=\"diffuse\" id=\"n\"><texture type=\"noise\" name=\"reflectance\"/></bsdf>\n"));
  EXPECT_TRUE(warned(imp, "a texture on 'alpha'"));
  EXPECT_TRUE(warned(imp, "texture 'noise' is not supported"));
  EXPECT_FALSE(imp.scene["materials"]["r"]["texture"]);
  EXPECT_FALSE(imp.scene["materials"]["n"]["texture"]);
  // A ref to something that is not a texture is an error at its line.
  try {
    import(xmlScene("<bsdf type=\"diffuse\" id=\"a\"/>\n<bsdf type=\"diffuse\" id=\"b\">\n<ref name=\"reflectance\" id=\"a\"/></bsdf>\n"));
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("test.xml:6:"), std::string::npos) << e.what();
  }
}

TEST(MitsubaTextures, EnvmapKeepsItsFileScaleAndRotation) {
  MitsubaImport imp = import(xmlScene(
      "<emitter type=\"envmap\"><string name=\"filename\" value=\"sky.exr\"/><float name=\"scale\" value=\"2.5\"/>"
      "<transform name=\"to_world\"><rotate y=\"1\" angle=\"90\"/></transform></emitter>\n"));
  YAML::Node l = imp.scene["lights"][0];
  EXPECT_EQ(l["type"].as<std::string>(), "environment");
  EXPECT_EQ(l["file"].as<std::string>(), "sky.exr");
  EXPECT_EQ(l["scale"].as<double>(), 2.5);
  // 90° about +y, row by row: x → −z, z → x.
  std::vector<double> r = numbers(l["rotation"]), want = {0, 0, 1, 0, 1, 0, -1, 0, 0};
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(r[size_t(i)], want[size_t(i)], 1e-12) << i;
  EXPECT_TRUE(warned(imp, "nearest"));
  // A scaled map is not a direction mapping; a format not read is dropped, said.
  EXPECT_THROW(import(xmlScene("<emitter type=\"envmap\"><string name=\"filename\" value=\"a.exr\"/>"
                               "<transform name=\"to_world\"><scale value=\"2\"/></transform></emitter>\n")), ConfigError);
  MitsubaImport hdr = import(xmlScene("<emitter type=\"envmap\"><string name=\"filename\" value=\"a.hdr\"/></emitter>\n"));
  EXPECT_EQ(hdr.scene["lights"][0]["file"].as<std::string>(), "a.hdr");  // Radiance HDR: read (core/image_input.h)
  MitsubaImport psd = import(xmlScene("<emitter type=\"envmap\"><string name=\"filename\" value=\"a.psd\"/></emitter>\n"));
  EXPECT_TRUE(warned(psd, "not an image format lightbench reads"));
  EXPECT_FALSE(psd.scene["lights"]);
}

TEST(MitsubaTextures, ThinDielectricPlasticAndDisk) {
  MitsubaImport imp = import(xmlScene(
      "<bsdf type=\"thindielectric\" id=\"t\"><string name=\"int_ior\" value=\"water\"/></bsdf>\n"
      "<bsdf type=\"plastic\" id=\"p\"><rgb name=\"diffuse_reflectance\" value=\"0.2, 0.3, 0.4\"/></bsdf>\n"
      "<shape type=\"disk\"><ref id=\"t\"/></shape>\n"));
  YAML::Node t = imp.scene["materials"]["t"];
  EXPECT_EQ(t["type"].as<std::string>(), "thin_dielectric");
  EXPECT_NEAR(t["ior"].as<double>(), 1.3330 / 1.000277, 1e-12);  // water over Mitsuba's default air
  EXPECT_FALSE(t["roughness"]);
  YAML::Node p = imp.scene["materials"]["p"];  // Mitsuba's model (core/bsdfs/plastic.h), its defaults
  EXPECT_EQ(p["type"].as<std::string>(), "plastic");
  EXPECT_EQ(numbers(p["albedo"]), (std::vector<double>{0.2, 0.3, 0.4}));
  EXPECT_NEAR(p["ior"].as<double>(), 1.49 / 1.000277, 1e-12);  // polypropylene over air
  EXPECT_EQ(p["roughness"].as<double>(), 0.0);
  EXPECT_FALSE(p["nonlinear"].as<bool>());
  EXPECT_FALSE(warned(imp, "coating"));  // only that it is one-sided in Mitsuba
  EXPECT_EQ(imp.scene["shapes"][0]["type"].as<std::string>(), "disk");
  EXPECT_TRUE(warned(imp, "256-sided polygon"));
}

// roughdiffuse: Oren–Nayar with the file's reflectance (0.x: diffuseReflectance
// too), alpha and useFastApprox, and Mitsuba's defaults (0.5, 0.2, full model).
TEST(MitsubaTextures, RoughDiffuseKeepsItsReflectanceAndRoughness) {
  MitsubaImport imp = import(xmlScene(
      "<bsdf type=\"roughdiffuse\" id=\"pot\"><rgb name=\"diffuseReflectance\" value=\"0.1\"/>"
      "<float name=\"alpha\" value=\"0.7\"/><boolean name=\"useFastApprox\" value=\"true\"/></bsdf>\n"
      "<bsdf type=\"roughdiffuse\" id=\"plain\"/>\n", "0.5.0"));
  YAML::Node pot = imp.scene["materials"]["pot"], plain = imp.scene["materials"]["plain"];
  EXPECT_EQ(pot["type"].as<std::string>(), "rough_diffuse");
  EXPECT_EQ(numbers(pot["albedo"]), (std::vector<double>{0.1, 0.1, 0.1}));
  EXPECT_DOUBLE_EQ(pot["roughness"].as<double>(), 0.7);
  EXPECT_TRUE(pot["fast_approximation"].as<bool>());
  EXPECT_EQ(numbers(plain["albedo"]), (std::vector<double>{0.5, 0.5, 0.5}));
  EXPECT_DOUBLE_EQ(plain["roughness"].as<double>(), 0.2);
  EXPECT_FALSE(plain["fast_approximation"].as<bool>());
  EXPECT_FALSE(warned(imp, "not supported"));
}

// As Mitsuba reads them: distribution and index names in any case; an alpha
// above 1 (which Mitsuba allows) clamped with a warning, not refused.
TEST(MitsubaTextures, NamesInAnyCaseAndAlphaAboveOne) {
  MitsubaImport imp = import(xmlScene(
      "<bsdf type=\"roughdielectric\" id=\"g\"><string name=\"distribution\" value=\"GGX\"/>"
      "<string name=\"int_ior\" value=\"BK7\"/><float name=\"alpha\" value=\"1.5\"/></bsdf>\n"));
  YAML::Node g = imp.scene["materials"]["g"];
  EXPECT_EQ(g["distribution"].as<std::string>(), "ggx");
  EXPECT_NEAR(g["ior"].as<double>(), 1.5046 / 1.000277, 1e-12);
  EXPECT_DOUBLE_EQ(g["roughness"].as<double>(), 1.0);
  EXPECT_TRUE(warned(imp, "alpha above 1 clamped"));
}

TEST(MitsubaTextures, SppmSettingsCarryOver) {
  MitsubaImport imp = import(xmlScene(
      "<integrator type=\"sppm\"><integer name=\"maxDepth\" value=\"9\"/><integer name=\"photonCount\" value=\"5000\"/>"
      "<float name=\"initialRadius\" value=\"0.05\"/><float name=\"alpha\" value=\"0.3\"/></integrator>\n", "0.5.0"));
  YAML::Node i = imp.scene["integrator"];
  EXPECT_EQ(i["name"].as<std::string>(), "sppm");
  EXPECT_EQ(i["photons_per_pass"].as<int>(), 5000);
  EXPECT_EQ(i["initial_radius"].as<double>(), 0.05);
  EXPECT_EQ(i["alpha"].as<double>(), 0.3);
  EXPECT_EQ(i["max_depth"].as<int>(), 9);
}

}  // namespace
}  // namespace lb

namespace lb {
namespace {

// Booleans and colours among a plastic's properties and those the importer
// passes over (a bitmap's storage settings) are accepted, not errors.
TEST(MitsubaTextures, PropertiesPassedOverMayHaveAnyType) {
  MitsubaImport imp = importMitsubaXmlFromString(
      "<scene version=\"3.0.0\"><sensor type=\"perspective\"/>\n"
      "<bsdf type=\"roughplastic\" id=\"p\"><boolean name=\"nonlinear\" value=\"true\"/>"
      "<rgb name=\"specular_reflectance\" value=\"0.5\"/><boolean name=\"sample_visible\" value=\"false\"/></bsdf>\n"
      "<bsdf type=\"diffuse\" id=\"d\"><texture type=\"bitmap\" name=\"reflectance\">"
      "<string name=\"filename\" value=\"a.png\"/><boolean name=\"accel\" value=\"false\"/>"
      "<string name=\"format\" value=\"fp16\"/></texture></bsdf>\n</scene>\n", "test.xml");
  YAML::Node p = imp.scene["materials"]["p"];
  EXPECT_EQ(p["type"].as<std::string>(), "plastic");
  EXPECT_TRUE(p["nonlinear"].as<bool>());
  EXPECT_EQ(numbers(p["specular"]), (std::vector<double>{0.5, 0.5, 0.5}));
  // roughplastic's defaults: Beckmann, alpha 0.1, separable masking.
  EXPECT_EQ(p["distribution"].as<std::string>(), "beckmann");
  EXPECT_EQ(p["masking"].as<std::string>(), "separable");
  EXPECT_NEAR(p["roughness"].as<double>(), 0.1, 1e-12);
  EXPECT_EQ(imp.scene["materials"]["d"]["texture"]["type"].as<std::string>(), "image");
}

}  // namespace
}  // namespace lb
