// The pbrt-v4 importer (core/pbrt/): each directive on a small file, pbrt's
// conventions (core/pbrt/import.h) each against a value worked out here from
// pbrt-v4's definitions, malformed input naming file:line:column, and the
// imported Cornell box rendering the same image as the Mitsuba one.
#include <gtest/gtest.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include "core/error.h"
#include "core/pbrt/params.h"
#include "tests/support/instancing_checks.h"
#include "tests/support/pbrt_snippets.h"
#include "tests/support/render_helpers.h"

namespace lb {
namespace {

using test::importPbrtSnippet;
using test::loadPbrtSnippet;
using test::pbrtErrorOf;

glm::dvec3 vec(const YAML::Node& n) { return {n[0].as<double>(), n[1].as<double>(), n[2].as<double>()}; }

// A shape's `transform: {matrix}` (row by row) applied to a point.
glm::dvec3 placed(const YAML::Node& shape, glm::dvec3 p) {
  glm::dmat4 m;
  for (int i = 0; i < 16; ++i) m[i % 4][i / 4] = shape["transform"]["matrix"][i].as<double>();
  return glm::dvec3(m * glm::dvec4(p, 1));
}

bool hasWarning(const ImportedScene& imp, const std::string& phrase) {
  for (const ImportWarning& w : imp.warnings)
    if ((w.element + ": " + w.message).find(phrase) != std::string::npos) return true;
  return false;
}

TEST(PbrtImport, TransformsComposeAsPbrtDefinesThem) {
  ImportedScene imp = importPbrtSnippet(
      "WorldBegin\n"
      "AttributeBegin\n"
      "  Translate 1 2 3\n"
      "  Rotate 90 0 0 1\n"    // counter-clockwise about +z: +x goes to +y
      "  Scale 2 2 2\n"
      "  Translate 1 0 0\n"    // so the sphere's centre is 1 + R(2·(1,0,0)) = (1, 4, 3)
      "  Shape \"sphere\" \"float radius\" 0.5\n"
      "AttributeEnd\n"
      "Shape \"sphere\"\n"     // the attribute block restored the identity
      // Column by column: the last four numbers hold the translation.
      "Transform [ 1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1 ]\n"
      "CoordinateSystem \"saved\"\n"
      "ConcatTransform [ 3 0 0 0  0 3 0 0  0 0 3 0  0 0 0 1 ]\n"
      "Shape \"sphere\"\n"
      "TransformBegin\n"
      "  Identity\n"
      "TransformEnd\n"
      "CoordSysTransform \"saved\"\n"
      "Shape \"sphere\"\n");
  YAML::Node s = imp.scene["shapes"];
  ASSERT_EQ(s.size(), 4u);
  glm::dvec3 c = vec(s[0]["center"]);
  EXPECT_NEAR(c.x, 1, 1e-12);
  EXPECT_NEAR(c.y, 4, 1e-12);
  EXPECT_NEAR(c.z, 3, 1e-12);
  EXPECT_DOUBLE_EQ(s[0]["radius"].as<double>(), 1.0);
  EXPECT_EQ(vec(s[1]["center"]), glm::dvec3(0));
  EXPECT_DOUBLE_EQ(s[1]["radius"].as<double>(), 1.0);
  EXPECT_EQ(vec(s[2]["center"]), glm::dvec3(5, 6, 7));
  EXPECT_DOUBLE_EQ(s[2]["radius"].as<double>(), 3.0);
  EXPECT_EQ(vec(s[3]["center"]), glm::dvec3(5, 6, 7));
  EXPECT_DOUBLE_EQ(s[3]["radius"].as<double>(), 1.0);
}

// Where world point `p` lands on the image of a scene whose camera is
// `cameraLines`, on a `w` × `h` film with fov 90.
glm::dvec2 rasterOf(const std::string& cameraLines, int w, int h, glm::dvec3 p) {
  SceneFile sf = loadPbrtSnippet(cameraLines + "Camera \"perspective\" \"float fov\" 90\n" +
                                 "Film \"rgb\" \"integer xresolution\" " + std::to_string(w) +
                                 " \"integer yresolution\" " + std::to_string(h) + "\nWorldBegin\n");
  auto r = sf.scene->camera.rasterOf(glm::normalize(Vec3(p) - sf.scene->camera.generateRay(Vec2(w / 2.f, h / 2.f)).o));
  EXPECT_TRUE(r.has_value());
  return r ? glm::dvec2(*r) : glm::dvec2(-1);
}

// pbrt's camera space is left-handed: +x is the image's right, +y up, +z
// ahead, and fov spans the shorter axis. With fov 90 on a 200 × 100 film
// (tan ½fov = 1 vertically, 2 horizontally), camera-space (1, 0, 1) lands at
// x = (1/2 + 1)/2 · 200 = 150 and (0, 1, 1) on the top edge.
TEST(PbrtImport, TheCameraKeepsPbrtsImageRightAndFovAxis) {
  const std::string lookAt = "LookAt 0 0 0  0 0 1  0 1 0\n";  // camera space = world space
  glm::dvec2 right = rasterOf(lookAt, 200, 100, {1, 0, 1});
  EXPECT_NEAR(right.x, 150, 1e-3);
  EXPECT_NEAR(right.y, 50, 1e-3);
  EXPECT_NEAR(rasterOf(lookAt, 200, 100, {0, 1, 1}).y, 0, 1e-3);
  // Portrait: fov spans x; (1, 0, 1) is on the right edge, (0, 1, 1) at y = (1 − ½)/2 · 200.
  EXPECT_NEAR(rasterOf(lookAt, 100, 200, {1, 0, 1}).x, 100, 1e-3);
  EXPECT_NEAR(rasterOf(lookAt, 100, 200, {0, 1, 1}).y, 50, 1e-3);
  // A mirroring world-to-camera matrix (Bitterli's exports; here Scale −1 1 1)
  // puts world +x on the left, as pbrt renders it.
  EXPECT_NEAR(rasterOf("Scale -1 1 1\n" + lookAt, 200, 100, {1, 0, 1}).x, 50, 1e-3);
  // The same through a matrix, and looking down −z from (0, 0, 5): pbrt's
  // +x = up × dir = y × (−z) = −x, so world −x is on the right.
  EXPECT_NEAR(rasterOf("LookAt 0 0 5  0 0 0  0 1 0\n", 200, 100, {-1, 0, 4}).x, 150, 1e-3);
}

TEST(PbrtImport, ACameraThatScalesIsRefused) {
  EXPECT_NE(pbrtErrorOf("Scale 1 1 2\nCamera \"perspective\"\nWorldBegin\n").find("test.pbrt:2:1: the camera transform scales"),
            std::string::npos);
  EXPECT_NE(pbrtErrorOf("Camera \"orthographic\"\n").find("not supported (only perspective)"), std::string::npos);
}

// pbrt's maxdepth counts bounces (0: emitters seen directly); lightbench's
// max_depth counts segments, one more.
TEST(PbrtImport, MaxDepthCountsBouncesSoLightbenchsIsOneMore) {
  auto integrator = [](const std::string& line) { return importPbrtSnippet(line + "WorldBegin\n").scene["integrator"]; };
  EXPECT_EQ(integrator("Integrator \"path\" \"integer maxdepth\" 0\n")["max_depth"].as<int>(), 1);
  EXPECT_EQ(integrator("Integrator \"bdpt\" \"integer maxdepth\" [ 6 ]\n")["max_depth"].as<int>(), 7);
  EXPECT_EQ(integrator("Integrator \"bdpt\"\n")["name"].as<std::string>(), "bdpt");
  EXPECT_EQ(integrator("")["max_depth"].as<int>(), 6);  // pbrt-v4's default, 5
  YAML::Node sppm = integrator("Integrator \"sppm\" \"integer maxdepth\" 8 \"float radius\" 0.01 "
                               "\"integer photonsperiteration\" 1000\n");
  EXPECT_EQ(sppm["name"].as<std::string>(), "sppm");
  EXPECT_EQ(sppm["max_depth"].as<int>(), 9);
  EXPECT_DOUBLE_EQ(sppm["initial_radius"].as<double>(), 0.01);
  EXPECT_EQ(sppm["photons_per_pass"].as<int>(), 1000);
  EXPECT_DOUBLE_EQ(sppm["alpha"].as<double>(), 2.0 / 3.0);  // fixed in pbrt-v4
  EXPECT_EQ(importPbrtSnippet("Integrator \"path\" \"integer maxdepth\" 4\nWorldBegin\n").sharedIntegratorKeys,
            std::vector<std::string>{"max_depth"});
}

// The emitting side of a one-sided area light, as pbrt-v4 orients it
// (Triangle::InteractionFromIntersection): the winding's normal, flipped by
// ReverseOrientation, not by a mirroring transform; a mesh with normals N
// emits on N's side (ReverseOrientation negates N too).
Vec3 emittingSide(const std::string& attributes, const std::string& normals = "") {
  SceneFile sf = loadPbrtSnippet("WorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\"\n" + attributes +
                                 "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ] " + normals + "\n"
                                 "AttributeEnd\n");
  EXPECT_EQ(sf.scene->shapes().size(), 1u);
  return sf.scene->shapes()[0].sampleArea(0.5f, Vec2(0.3f, 0.3f)).n;
}

TEST(PbrtImport, TrianglesFaceAsInPbrt) {
  EXPECT_GT(emittingSide("").z, 0.99f);
  EXPECT_LT(emittingSide("ReverseOrientation\n").z, -0.99f);
  // Scale 1 1 −1 mirrors: pbrt's normal is the transformed normal, −z.
  EXPECT_LT(emittingSide("Scale 1 1 -1\n").z, -0.99f);
  EXPECT_GT(emittingSide("Scale 1 1 -1\nReverseOrientation\n").z, 0.99f);
  const std::string down = "\"normal N\" [ 0 0 -1  0 0 -1  0 0 -1 ]";
  EXPECT_LT(emittingSide("", down).z, -0.99f);
  EXPECT_GT(emittingSide("ReverseOrientation\n", down).z, 0.99f);
}

TEST(PbrtImport, SpheresAndDisksFaceAsInPbrt) {
  auto shapes = [](const std::string& attributes) {
    return importPbrtSnippet("WorldBegin\n" + attributes + "Shape \"sphere\"\nShape \"disk\" \"float radius\" 2 \"float height\" 1\n")
        .scene["shapes"];
  };
  EXPECT_FALSE(shapes("")[0]["flip_normals"]);
  EXPECT_TRUE(shapes("ReverseOrientation\n")[0]["flip_normals"].as<bool>());
  // pbrt-v4's quadrics flip when ReverseOrientation and a mirror differ.
  EXPECT_TRUE(shapes("Scale -1 1 1\n")[0]["flip_normals"].as<bool>());
  // A disk's normal is the transformed +z, flipped only by ReverseOrientation.
  EXPECT_FALSE(shapes("Scale -1 1 1\n")[1]["flip_normals"]);
  EXPECT_TRUE(shapes("ReverseOrientation\n")[1]["flip_normals"].as<bool>());
  // Disk: radius 2 at height 1.
  glm::dvec3 rim = placed(shapes("")[1], {1, 0, 0});
  EXPECT_EQ(rim, glm::dvec3(2, 0, 1));
}

// pbrt-v4 normalises light spectra to luminance 1 (an rgb L stays itself on
// an sRGB film) and rescales by power or illuminance (lights.cpp, *::Create).
TEST(PbrtImport, LightsAreNormalisedAsInPbrtV4) {
  ImportedScene imp = importPbrtSnippet(
      "WorldBegin\n"
      "AttributeBegin\n"
      "AreaLightSource \"diffuse\" \"rgb L\" [ 1 2 3 ] \"float scale\" 2 \"bool twosided\" true\n"
      "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  2 0 0  2 2 0  0 2 0 ] \"integer indices\" [ 0 1 2  0 2 3 ]\n"
      "AttributeEnd\n"
      "AttributeBegin\n"
      "AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ] \"float power\" 100\n"
      "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  2 0 0  2 2 0  0 2 0 ] \"integer indices\" [ 0 1 2  0 2 3 ]\n"
      "AttributeEnd\n"
      "LightSource \"point\" \"point3 from\" [ 1 2 3 ] \"float power\" 50\n"
      "LightSource \"spot\" \"float coneangle\" 40 \"float conedeltaangle\" 10 \"float power\" 10\n"
      "LightSource \"distant\" \"point3 from\" [ 0 1 0 ] \"point3 to\" [ 0 0 0 ] \"rgb L\" [ 1 0.5 1 ] \"float illuminance\" 3\n"
      "LightSource \"infinite\" \"float illuminance\" 2\n");
  YAML::Node s = imp.scene["shapes"], l = imp.scene["lights"];
  EXPECT_EQ(vec(s[0]["emission"]), glm::dvec3(2, 4, 6));
  EXPECT_TRUE(s[0]["two_sided"].as<bool>());
  // 100 W from a one-sided 2 × 2 quad: L = Φ / (π A).
  EXPECT_NEAR(s[1]["emission"][0].as<double>(), 100 / (M_PI * 4), 1e-9);
  EXPECT_NEAR(l[0]["intensity"][1].as<double>(), 50 / (4 * M_PI), 1e-9);
  EXPECT_EQ(vec(l[0]["position"]), glm::dvec3(1, 2, 3));
  // A smoothstep cone from 30° to 40°: solid angle 2π((1 − cos 30°) + (cos 30° − cos 40°)/2).
  double omega = 2 * M_PI * ((1 - std::cos(M_PI / 6)) + (std::cos(M_PI / 6) - std::cos(40 * M_PI / 180)) / 2);
  EXPECT_NEAR(l[1]["intensity"][0].as<double>(), 10 / omega, 1e-9);
  EXPECT_DOUBLE_EQ(l[1]["falloff_start"].as<double>(), 30.0);
  // Light from +y travels down.
  EXPECT_EQ(vec(l[2]["direction"]), glm::dvec3(0, -1, 0));
  EXPECT_EQ(vec(l[2]["irradiance"]), glm::dvec3(3, 1.5, 3));
  // A constant sky of radiance L gives an upward surface πL.
  EXPECT_NEAR(l[3]["radiance"][0].as<double>(), 2 / M_PI, 1e-12);
}

// The Planckian locus's chromaticity from Kim et al.'s cubic fit (US patent
// 7024034; valid 4000–25000 K), an independent reference for blackbodyRgb.
glm::dvec2 planckianXy(double t) {
  double x = -3.0258469e9 / (t * t * t) + 2.1070379e6 / (t * t) + 0.2226347e3 / t + 0.240390;
  double y = 3.0817580 * x * x * x - 5.87338670 * x * x + 3.75112997 * x - 0.37001483;
  return {x, y};
}

TEST(PbrtImport, BlackbodiesHaveThePlanckianColourAtLuminanceOne) {
  for (double t : {4500.0, 6500.0, 10000.0}) {
    glm::dvec3 rgb = pbrt::blackbodyRgb(t);
    // linear sRGB → XYZ (IEC 61966-2-1)
    glm::dvec3 xyz(0.4124 * rgb.r + 0.3576 * rgb.g + 0.1805 * rgb.b, 0.2126 * rgb.r + 0.7152 * rgb.g + 0.0722 * rgb.b,
                   0.0193 * rgb.r + 0.1192 * rgb.g + 0.9505 * rgb.b);
    double sum = xyz.x + xyz.y + xyz.z;
    glm::dvec2 expected = planckianXy(t);
    EXPECT_NEAR(xyz.y, 1, 0.01) << t;
    EXPECT_NEAR(xyz.x / sum, expected.x, 0.003) << t;
    EXPECT_NEAR(xyz.y / sum, expected.y, 0.003) << t;
  }
}

TEST(PbrtImport, MaterialsMapOntoLightbenchsWithPbrtsDefaults) {
  ImportedScene imp = importPbrtSnippet(
      "WorldBegin\n"
      "MakeNamedMaterial \"copper\" \"string type\" \"conductor\"\n"  // pbrt-v4's default metal is copper
      "MakeNamedMaterial \"silver\" \"string type\" \"conductor\" \"spectrum eta\" \"metal-Ag-eta\" "
      "\"spectrum k\" \"metal-Ag-k\" \"float roughness\" 0.04\n"
      "MakeNamedMaterial \"raw\" \"string type\" \"conductor\" \"float roughness\" 0.04 \"bool remaproughness\" false\n"
      "MakeNamedMaterial \"artist\" \"string type\" \"conductor\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
      "MakeNamedMaterial \"glass\" \"string type\" \"dielectric\" \"spectrum eta\" \"glass-BK7\"\n"
      "MakeNamedMaterial \"pane\" \"string type\" \"thindielectric\"\n"
      "MakeNamedMaterial \"plastic\" \"string type\" \"coateddiffuse\" \"rgb reflectance\" [ 0.2 0.3 0.4 ]\n"
      "MakeNamedMaterial \"coated\" \"string type\" \"coatedconductor\" \"float interface.roughness\" 0.09 "
      "\"spectrum conductor.eta\" \"metal-Au-eta\" \"spectrum conductor.k\" \"metal-Au-k\" \"float conductor.roughness\" 0.16 "
      "\"float thickness\" 0.05 \"rgb albedo\" [0.5 0.5 0.5]\n"
      "Material \"diffuse\"\n"
      "Shape \"sphere\"\n");
  YAML::Node m = imp.scene["materials"];
  EXPECT_FLOAT_EQ(m["copper"]["eta"][1].as<float>(), 0.924033f);
  EXPECT_FLOAT_EQ(m["silver"]["k"][0].as<float>(), 4.82835f);
  EXPECT_DOUBLE_EQ(m["silver"]["roughness"].as<double>(), 0.2);  // sqrt(0.04)
  EXPECT_DOUBLE_EQ(m["raw"]["roughness"].as<double>(), 0.04);
  EXPECT_EQ(m["raw"]["distribution"].as<std::string>(), "ggx");
  // Reflectance r at normal incidence with eta 1: ((k² )/(4 + k²)) = r for k = 2√r/√(1−r).
  double k = m["artist"]["k"][0].as<double>();
  EXPECT_NEAR(k * k / (4 + k * k), 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(m["glass"]["ior"].as<double>(), 1.5168);
  EXPECT_EQ(m["pane"]["type"].as<std::string>(), "thin_dielectric");
  EXPECT_DOUBLE_EQ(m["pane"]["ior"].as<double>(), 1.5);
  // coateddiffuse: pbrt-v4's layered BSDF with its defaults (eta 1.5, a
  // smooth coating, thickness 0.01, 10 bounces, 1 sample).
  EXPECT_EQ(m["plastic"]["type"].as<std::string>(), "coated_diffuse");
  EXPECT_DOUBLE_EQ(m["plastic"]["albedo"][2].as<double>(), 0.4);
  EXPECT_DOUBLE_EQ(m["plastic"]["ior"].as<double>(), 1.5);
  EXPECT_DOUBLE_EQ(m["plastic"]["roughness"].as<double>(), 0.0);
  EXPECT_DOUBLE_EQ(m["plastic"]["thickness"].as<double>(), 0.01);
  EXPECT_EQ(m["plastic"]["max_depth"].as<int>(), 10);
  EXPECT_EQ(m["plastic"]["samples"].as<int>(), 1);
  EXPECT_FALSE(hasWarning(imp, "coateddiffuse"));
  // coatedconductor: its interface. and conductor. parameters, both roughnesses remapped.
  EXPECT_EQ(m["coated"]["type"].as<std::string>(), "coated_conductor");
  EXPECT_DOUBLE_EQ(m["coated"]["roughness"].as<double>(), 0.3);
  EXPECT_DOUBLE_EQ(m["coated"]["conductor_roughness"].as<double>(), 0.4);
  EXPECT_DOUBLE_EQ(m["coated"]["thickness"].as<double>(), 0.05);
  EXPECT_NE(m["coated"]["conductor_eta"][1].as<float>(), 0.924033f) << "gold's, not the default copper's";
  EXPECT_TRUE(hasWarning(imp, "scattering medium between the layers"));
  EXPECT_DOUBLE_EQ(m["diffuse"]["albedo"][0].as<double>(), 0.5);
  EXPECT_EQ(imp.scene["shapes"][0]["material"].as<std::string>(), "diffuse");
}

// pbrt-v4's bump map (a material's float "displacement" texture), normal map
// (an image file of linear values, looked up at (u, 1 − v)) and alpha (the
// shape's, a number or a float texture: a copy of its material with the
// opacity, so other shapes of that material stay opaque).
TEST(PbrtImport, DisplacementNormalMapsAndAlphaBecomeSurfaceMaps) {
  ImportedScene imp = importPbrtSnippet(
      "WorldBegin\n"
      "Texture \"height\" \"float\" \"imagemap\" \"string filename\" \"h.exr\"\n"
      "Texture \"cut\" \"float\" \"checkerboard\" \"float tex1\" 1 \"float tex2\" 0\n"
      "MakeNamedMaterial \"bumpy\" \"string type\" \"diffuse\" \"texture displacement\" \"height\"\n"
      "MakeNamedMaterial \"mapped\" \"string type\" \"conductor\" \"string normalmap\" \"n.png\"\n"
      "MakeNamedMaterial \"leaf\" \"string type\" \"diffuse\"\n"
      "NamedMaterial \"bumpy\"\n"
      "Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]\n"
      "NamedMaterial \"mapped\"\n"
      "Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]\n"
      "NamedMaterial \"leaf\"\n"
      "Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0] \"texture alpha\" \"cut\"\n"
      "Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0] \"float alpha\" 0.25\n"
      "Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]\n"
      "Shape \"sphere\" \"float alpha\" 0.5\n"
      "Texture \"height\" \"spectrum\" \"imagemap\" \"string filename\" \"colour.png\"\n"  // its own namespace
      "Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0] \"texture alpha\" \"cut\"\n");
  const YAML::Node& m = imp.scene["materials"];
  const YAML::Node& shapes = imp.scene["shapes"];
  auto of = [&](int i) { return m[shapes[i]["material"].as<std::string>()]; };
  EXPECT_EQ(of(0)["bump_map"]["file"].as<std::string>(), "h.exr");
  EXPECT_EQ(of(1)["normal_map"]["file"].as<std::string>(), "n.png");
  EXPECT_FALSE(of(1)["normal_map"]["srgb"].as<bool>());
  EXPECT_DOUBLE_EQ(of(1)["normal_map"]["uv_transform"][4].as<double>(), -1.0);  // v flipped, as pbrt's imagemap
  EXPECT_DOUBLE_EQ(of(1)["normal_map"]["uv_transform"][5].as<double>(), 1.0);
  EXPECT_EQ(of(2)["opacity"]["type"].as<std::string>(), "checkerboard");
  EXPECT_EQ(of(2)["type"].as<std::string>(), "diffuse");
  EXPECT_DOUBLE_EQ(of(3)["opacity"].as<double>(), 0.25);
  EXPECT_FALSE(of(4)["opacity"]) << "the material itself stays opaque";
  EXPECT_FALSE(of(5)["opacity"]) << "spheres take no opacity";
  EXPECT_TRUE(hasWarning(imp, "alpha on a sphere not supported"));
  EXPECT_EQ(shapes[6]["material"].as<std::string>(), shapes[2]["material"].as<std::string>()) << "one copy per (material, alpha)";
  EXPECT_FALSE(hasWarning(imp, "displacement"));
  EXPECT_FALSE(hasWarning(imp, "normalmap"));
  EXPECT_FALSE(hasWarning(imp, "float textures"));
}

TEST(PbrtImport, PixelFiltersAndSamplersMapWithPbrtsDefaults) {
  auto options = [](const std::string& lines) { return importPbrtSnippet(lines + "WorldBegin\n"); };
  YAML::Node f = options("PixelFilter \"triangle\" \"float xradius\" 1 \"float yradius\" 1\n").scene["film"]["filter"];
  EXPECT_EQ(f["type"].as<std::string>(), "tent");
  EXPECT_DOUBLE_EQ(f["radius"].as<double>(), 1.0);
  f = options("").scene["film"]["filter"];  // pbrt-v4's default: gaussian, radius 1.5, sigma 0.5
  EXPECT_EQ(f["type"].as<std::string>(), "gaussian");
  EXPECT_DOUBLE_EQ(f["radius"].as<double>(), 1.5);
  EXPECT_DOUBLE_EQ(f["sigma"].as<double>(), 0.5);
  f = options("PixelFilter \"sinc\"\n").scene["film"]["filter"];
  EXPECT_EQ(f["type"].as<std::string>(), "lanczos");
  EXPECT_DOUBLE_EQ(f["radius"].as<double>(), 4.0);
  EXPECT_DOUBLE_EQ(f["tau"].as<double>(), 3.0);
  ImportedScene wide = options("PixelFilter \"box\" \"float xradius\" 1 \"float yradius\" 0.5\n");
  EXPECT_DOUBLE_EQ(wide.scene["film"]["filter"]["radius"].as<double>(), 1.0);
  EXPECT_TRUE(hasWarning(wide, "the larger is used"));
  ImportedScene s = options("Sampler \"zsobol\" \"integer pixelsamples\" 32\nFilm \"rgb\" \"integer xresolution\" 64\n");
  EXPECT_EQ(s.sampleCount, 32u);
  EXPECT_EQ(s.scene["sampler"]["type"].as<std::string>(), "zsobol");
  EXPECT_EQ(s.scene["film"]["width"].as<int>(), 64);
  EXPECT_EQ(s.scene["film"]["height"].as<int>(), 720);  // pbrt-v4's default
  EXPECT_EQ(options("").sampleCount, 16u);
}

TEST(PbrtImport, IncludeReadsFilesBesideTheMainOneAndObjectsAreInstanced) {
  std::filesystem::path dir = std::filesystem::temp_directory_path() / ("lb_pbrt_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir / "parts");
  std::ofstream(dir / "parts" / "geometry.pbrt") << "Shape \"sphere\" \"float radius\" 2\nShape \"cylinder\"\n";
  std::ofstream(dir / "main.pbrt") << "WorldBegin\n"
                                      "Include \"parts/geometry.pbrt\"\n"
                                      "ObjectBegin \"ball\"\n"
                                      "  Translate 0 1 0\n"
                                      "  Shape \"sphere\"\n"
                                      "ObjectEnd\n"
                                      "Translate 10 0 0\n"
                                      "ObjectInstance \"ball\"\n"
                                      "Translate 10 0 0\n"
                                      "ObjectInstance \"ball\"\n";
  ImportedScene imp = importPbrt((dir / "main.pbrt").string());
  YAML::Node s = imp.scene["shapes"];
  ASSERT_EQ(s.size(), 3u);
  EXPECT_DOUBLE_EQ(s[0]["radius"].as<double>(), 2.0);
  // The object's shape in its own space (its CTM inside ObjectBegin) ...
  YAML::Node ball = imp.scene["objects"]["ball"];
  ASSERT_EQ(ball.size(), 1u);
  EXPECT_EQ(vec(ball[0]["center"]), glm::dvec3(0, 1, 0));
  // ... placed by each instance with the CTM at ObjectInstance (Embree instancing).
  for (int i : {1, 2}) {
    EXPECT_EQ(s[i]["type"].as<std::string>(), "instance");
    EXPECT_EQ(s[i]["object"].as<std::string>(), "ball");
    EXPECT_DOUBLE_EQ(s[i]["transform"]["matrix"][3].as<double>(), 10.0 * i);  // row 0, column 3: x translation
  }
  SceneFile loaded = loadScene((dir / "main.pbrt").string());
  EXPECT_EQ(loaded.scene->instanceCount(), 2u);
  SurfaceInteraction si;
  ASSERT_TRUE(loaded.scene->intersect(Ray{Vec3(20, 1, 5), Vec3(0, 0, -1), Infinity}, si));
  EXPECT_NEAR(si.p.z, 1.0f, 1e-5f);  // the unit sphere at (20, 1, 0)
  // The warning from the included file names it and its line, at the Include's line.
  ASSERT_EQ(imp.warnings.size(), 1u);
  EXPECT_EQ(imp.warnings[0].line, 2);
  EXPECT_NE(imp.warnings[0].element.find("geometry.pbrt:2"), std::string::npos) << imp.warnings[0].element;
  std::filesystem::remove_all(dir);
}

// What instancing leaves out is said: an area light inside an object (pbrt-v4
// ignores it too) and a mirroring instance (lightbench's winding rule turns
// its triangles over); an object whose every shape was dropped places nothing.
TEST(PbrtImport, InstancingGapsAreWarnedAndEmptyObjectsPlaceNothing) {
  ImportedScene imp = importPbrtSnippet(
      "WorldBegin\n"
      "ObjectBegin \"lamp\"\n"
      "  AreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\n"
      "  Shape \"sphere\"\n"
      "ObjectEnd\n"
      "ObjectBegin \"nothing\"\n"
      "  Shape \"cylinder\"\n"
      "ObjectEnd\n"
      "Scale -1 1 1\n"
      "ObjectInstance \"lamp\"\n"
      "ObjectInstance \"nothing\"\n");
  EXPECT_TRUE(hasWarning(imp, "area lights in object instances are not supported"));
  EXPECT_TRUE(hasWarning(imp, "mirroring transform"));
  test::expectLampWithoutEmissionAndNothingPlaced(imp.scene);
}

TEST(PbrtImport, EachUnsupportedKindIsWarnedOnceWithItsLines) {
  ImportedScene imp = importPbrtSnippet(
      "WorldBegin\n"
      "Shape \"cylinder\"\n"
      "Shape \"sphere\" \"float foo\" 1\n"
      "Shape \"cylinder\"\n"
      "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\n");
  ASSERT_EQ(imp.warnings.size(), 3u);
  EXPECT_EQ(imp.warnings[0].line, 2);
  EXPECT_NE(imp.warnings[0].message.find("not supported; dropped (also line 4)"), std::string::npos) << imp.warnings[0].message;
  EXPECT_NE(imp.warnings[1].message.find("\"float foo\""), std::string::npos);
  EXPECT_NE(imp.warnings[2].message.find("media"), std::string::npos);
}

// One error per token class and structural mistake, each at file:line:column.
TEST(PbrtImport, MalformedInputIsOneErrorAtFileLineAndColumn) {
  const std::string file = std::string(LIGHTBENCH_SOURCE_DIR) + "/scenes/test.pbrt:";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"WorldBegin\nShape \"sphere\n", "2:7: unterminated string"},
      {"WorldBegin\nShape \"sphere\" \"float radius\" [ 1x ]\n", "2:33: expected a finite number"},
      {"WorldBegin\nShape \"sphere\" \"float radius\" [ 1\n", "3:1: end of file inside the values"},
      {"WorldBegin\nShpe \"sphere\"\n", "2:1: unknown directive 'Shpe'"},
      {"WorldBegin\nshape \"sphere\"\n", "did you mean 'Shape'"},
      {"WorldBegin\nShape \"sphere\" \"flot radius\" 1\n", "2:16: unknown parameter type 'flot'"},
      {"WorldBegin\nShape \"sphere\" \"radius\" 1\n", "2:16: expected a parameter declaration"},
      {"WorldBegin\nAreaLightSource \"diffuse\" \"bool twosided\" maybe\n", "2:43: expected true or false"},
      {"Film \"rgb\" \"integer xresolution\" 1.5\n", "1:34: expected an integer"},
      {"WorldBegin\nAttributeEnd\n", "2:1: AttributeEnd without AttributeBegin"},
      {"Transform 1 0 0 0\n", "1:11: Transform expects [ 16 numbers ]"},
      {"Translate 1 2\n", "2:1: Translate expects numbers, got the end of the file"},
      {"WorldBegin\nShape \"sphere\" \"string s\" \"a\\qb\"\n", "2:29: unknown escape"},
      {"WorldBegin\n[ 1 ]\n", "2:1: expected a directive"},
      {"WorldBegin\nNamedMaterial \"nope\"\n", "2:1: NamedMaterial \"nope\" is not defined"},
      {"WorldBegin\nShape \"sphere\"\nCamera \"perspective\"\n", "3:1: Camera is only allowed before WorldBegin"},
      {"WorldBegin\nShape \"sphere\" \"float radius\" 1 \"float radius\" 2\n", "2:33: parameter 'radius' given twice"},
      {"WorldBegin\nShape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] \"integer indices\" [ 0 1 3 ]\n",
       "'indices': index 3 is outside the 3 vertices"},
      {"WorldBegin\nInclude \"missing.pbrt\"\n", "2:9: cannot read"},
      {"WorldBegin\nAttributeBegin\n", "end of file inside AttributeBegin"},
      // Found in review: an AttributeEnd popped ObjectBegin's state and ObjectEnd read an empty stack.
      {"WorldBegin\nObjectBegin \"a\"\nAttributeEnd\nObjectEnd\n", "3:1: AttributeEnd where the innermost open block is ObjectBegin"},
      {"WorldBegin\nObjectBegin \"a\"\nTransformBegin\nObjectEnd\n", "4:1: ObjectEnd inside an open"},
      {"Scale 1e300 1 1\nScale 1e300 1 1\n", "2:1: Scale: the transformation matrix is no longer finite"},
      {"WorldBegin\nLightSource \"point\" \"blackbody I\" 10\n", "in [500, 1e6]"},
  };
  for (const auto& [text, expected] : cases) {
    std::string e = pbrtErrorOf(text);
    EXPECT_NE(e.find(expected), std::string::npos) << "input:\n" << text << "error: " << e;
    if (expected.find(':') == 1 || expected.find(':') == 2) {
      EXPECT_EQ(e.rfind(file, 0), 0u) << "not at the start: " << e;
    }
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
}

// `type: triangles`, the YAML form trianglemesh imports to: a rectangle
// written as its two triangles renders the rectangle's image bit for bit.
TEST(PbrtImport, InlineTrianglesRenderAsTheSameMeshWrittenAsARectangle) {
  const std::string common =
      "camera: {position: [0, 0, 4], look_at: [0, 0, 0]}\nfilm: {width: 16, height: 16}\n"
      "lights: [{type: point, position: [0, 1, 3], intensity: 5}]\nshapes:\n";
  SceneFile rect = loadSceneFromString(common + "  - {type: rectangle, transform: {rotate_z: 10}}\n", "a.yaml");
  SceneFile tris = loadSceneFromString(
      common + "  - {type: triangles, transform: {rotate_z: 10}, positions: [-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0],\n"
               "     indices: [0, 1, 2, 0, 2, 3], uvs: [0, 0, 1, 0, 1, 1, 0, 1]}\n",
      "b.yaml");
  test::RenderSpec spec;
  spec.spp = 4;
  auto a = test::renderScene(rect, spec), b = test::renderScene(tris, spec);
  Image ia = a->image(), ib = b->image();
  EXPECT_TRUE(ia.pixels == ib.pixels);
}

// Bitterli's Cornell box in pbrt-v4 form (inline triangle meshes, one
// emitting quad) and in Mitsuba form (rectangles and cubes) render the same
// image in expectation: per-region z-tests at a Šidák-corrected 1e-3, as the
// Mitsuba box against the hand-written YAML one (mitsuba_import_test.cpp).
TEST(PbrtImport, ImportedCornellBoxMatchesTheMitsubaOne) {
  YAML::Node size = YAML::Load("{film: {width: 24, height: 24}}");
  SceneLoadOptions quiet;
  quiet.quiet = true;
  SceneFile pbrt = loadScene(test::sourcePath("scenes/external/cornell-box/pbrt/scene-v4.pbrt"), size, quiet);
  SceneFile xml = loadScene(test::sourcePath("scenes/external/cornell-box/scene.xml"), size, quiet);
  test::RenderSpec spec;
  spec.params = "{max_depth: 8}";
  spec.spp = 1024;
  spec.seed = 21;
  std::string failures = test::compareScenes(pbrt, xml, spec);
  EXPECT_TRUE(failures.empty()) << failures;
}

}  // namespace
}  // namespace lb

namespace lb {
namespace {

// An imported shape of zero area is dropped with a warning (Mitsuba and pbrt
// show nothing there), where YAML refuses it; an emitting one stays an error.
TEST(PbrtImport, AShapeOfZeroAreaIsDroppedNotRefused) {
  const std::string flat = "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  2 0 0 ]\n";
  SceneFile sf = loadPbrtSnippet("WorldBegin\nShape \"sphere\"\n" + flat);
  EXPECT_EQ(sf.scene->shapes().size(), 1u);
  bool warned = false;
  for (const std::string& w : sf.warnings) warned |= w.find("every triangle is degenerate") != std::string::npos;
  EXPECT_TRUE(warned);
  EXPECT_THROW(loadPbrtSnippet("WorldBegin\nAreaLightSource \"diffuse\"\n" + flat), ConfigError);
}

}  // namespace
}  // namespace lb

namespace lb {
namespace {

// Textures on a diffuse reflectance, evaluated through lightbench's texture
// at uvs where pbrt's definitions give the answer: a checkerboard's tex1 where
// ⌊s⌋ + ⌊t⌋ is even (s = 4u, t = 2v here), and an imagemap's texel at (s, 1 − t).
TEST(PbrtImport, CheckerboardAndImagemapTexturesLookUpWherePbrtDoes) {
  ImportedScene imp = importPbrtSnippet(
      "WorldBegin\n"
      "Texture \"checks\" \"spectrum\" \"checkerboard\" \"float uscale\" 4 \"float vscale\" 2 "
      "\"rgb tex1\" [ 0.9 0.9 0.9 ] \"rgb tex2\" [ 0.1 0.1 0.1 ]\n"
      "Texture \"photo\" \"spectrum\" \"imagemap\" \"string filename\" \"maps/x.png\" \"float vdelta\" 0.25\n"
      "Material \"diffuse\" \"texture reflectance\" \"checks\"\n"
      "Shape \"sphere\"\n"
      "Material \"diffuse\" \"texture reflectance\" \"photo\"\n"
      "Shape \"sphere\"\n");
  YAML::Node checks = imp.scene["materials"]["diffuse"]["texture"], photo = imp.scene["materials"]["diffuse_2"]["texture"];
  ASSERT_TRUE(checks && photo);
  auto apply = [](const YAML::Node& t, double u, double v) {
    const YAML::Node& m = t["uv_transform"];
    return glm::dvec2(m[0].as<double>() * u + m[1].as<double>() * v + m[2].as<double>(),
                      m[3].as<double>() * u + m[4].as<double>() * v + m[5].as<double>());
  };
  for (double u : {0.05, 0.3, 0.55, 0.8})
    for (double v : {0.1, 0.4, 0.7, 0.95}) {
      bool pbrtTex1 = (int(std::floor(4 * u)) + int(std::floor(2 * v))) % 2 == 0;
      glm::dvec2 w = apply(checks, u, v);
      bool lightbenchColor0 = (int(std::floor(2 * w.x)) - int(std::floor(2 * w.y))) % 2 == 0;
      EXPECT_EQ(pbrtTex1, lightbenchColor0) << u << " " << v;
      // The imagemap: pbrt's image row is 1 − (v + 0.25) from the top.
      glm::dvec2 q = apply(photo, u, v);
      EXPECT_NEAR(q.x, u, 1e-12);
      EXPECT_NEAR(q.y, 1 - (v + 0.25), 1e-12);
    }
  EXPECT_DOUBLE_EQ(checks["color0"][0].as<double>(), 0.9);
  EXPECT_TRUE(photo["srgb"].as<bool>());
}

}  // namespace
}  // namespace lb
