// pbrt-v4 materials (src/pbrt/materials.cpp, with the User's Guide's
// defaults) as lightbench materials (core/bsdfs/material_factory.cpp). Where
// lightbench has no counterpart yet, a warning says what stands in for it.
#include <cmath>
#include "core/error.h"
#include "core/pbrt/translator.h"

namespace lb::pbrt {
namespace {

// A colour parameter that may be given as a texture; textures are not read
// yet, so a texture stands for the default (warned by the caller).
struct ColorParam {
  glm::dvec3 rgb;
  bool textured = false;
  std::string approximation;
};

ColorParam colorParam(const ParamSet& ps, const std::string& name, glm::dvec3 fallback) {
  const Param* p = ps.find(name);
  if (p && p->type == "texture") return {fallback, true, ""};
  auto c = ps.getColor(name, false);
  if (!c) return {fallback, false, ""};
  return {c->rgb, false, c->approximation};
}

}  // namespace

std::string Translator::addMaterial(const std::string& preferredName, YAML::Node m) {
  std::string name = preferredName.empty() ? "material" : preferredName;
  if (name == "none" || materialNames_.count(name)) {
    int k = 2;
    while (materialNames_.count(name + "_" + std::to_string(k))) ++k;
    name += "_" + std::to_string(k);
  }
  materialNames_.insert(name);
  materials_[name] = m;
  if (interfaceNext_) interfaceMaterials_.insert(name);
  interfaceNext_ = false;
  return name;
}

// pbrt-v4's imagemap and 2D checkerboard (textures.cpp) as lightbench's image
// and checkerboard textures. pbrt looks an image up at (s, 1 − t) with
// (s, t) = (su·u + du, sv·v + dv) and uvs as the shapes have them; lightbench
// at (u', v') with v' down the image, so uv_transform = [su, 0, du, 0, −sv, 1 − dv].
// The checkerboard compares ⌊s⌋ + ⌊t⌋ with no flip: [su, 0, du, 0, sv, dv] / 2.
YAML::Node Translator::texture(const std::string& texClass, const std::string& type, const ParamSet& ps, const Where& at) {
  YAML::Node t(YAML::NodeType::Map);
  double su = ps.getFloat("uscale", 1), sv = ps.getFloat("vscale", 1), du = ps.getFloat("udelta", 0), dv = ps.getFloat("vdelta", 0);
  if (const Param* p = ps.find("mapping"); p && !p->strings.empty() && p->strings[0] != "uv") {
    warn(at, "mapping '" + p->strings[0] + "' not supported; uv used");
  }
  if (type == "imagemap") {
    std::string file = ps.getString("filename", "");
    if (file.empty()) throw ConfigError(at.file, at.line, at.column, "filename", "an imagemap needs \"string filename\"");
    t["type"] = "image";
    t["file"] = file;
    std::string encoding = ps.getString("encoding", "sRGB");
    if (encoding != "sRGB" && encoding != "linear") warn(at, "encoding '" + encoding + "' read as sRGB");
    t["srgb"] = encoding != "linear";
    std::string filter = ps.getString("filter", "bilinear");
    t["filter"] = filter == "point" ? "nearest" : "bilinear";
    if (filter != "point" && filter != "bilinear") warn(at, "filter '" + filter + "' (mip-mapped) approximated as bilinear");
    if (ps.getString("wrap", "repeat") != "repeat") warn(at, "wrap modes other than repeat read as repeat");
    if (ps.getBool("invert", false)) warn(at, "invert not supported; ignored");
    if (ps.getFloat("scale", 1) != 1) warn(at, "scale not supported; ignored");
  } else if (type == "checkerboard") {
    if (ps.getInt("dimension", 2) != 2) {
      ps.markAllUsed();
      warn(at, "a 3D checkerboard not supported; dropped");
      return YAML::Node();
    }
    // pbrt: tex1 where ⌊s⌋ + ⌊t⌋ is even; lightbench's color0 where ⌊2u'⌋ and ⌊2v'⌋ have the same parity.
    t["type"] = "checkerboard";
    auto value = [&](const char* name, double fallback) {
      auto c = ps.getColor(name, false);
      return flowVec(c ? c->rgb : glm::dvec3(fallback));
    };
    t["color0"] = value("tex1", 1);
    t["color1"] = value("tex2", 0);
    su /= 2, sv /= 2, du /= 2, dv /= 2;
  } else {
    ps.markAllUsed();
    warn(at, "texture '" + type + "' not supported; materials that use it take their default value");
    return YAML::Node();
  }
  YAML::Node m(YAML::NodeType::Sequence);
  m.SetStyle(YAML::EmitterStyle::Flow);
  // The checkerboard is not an image lookup: no flip of v.
  bool image = type == "imagemap";
  for (double x : {su, 0.0, du, 0.0, image ? -sv : sv, image ? 1 - dv : dv}) m.push_back(x);
  t["uv_transform"] = m;
  warnUnused(ps, at);
  return t;
}

YAML::Node Translator::material(const std::string& type, const ParamSet& ps, const Where& at) {
  YAML::Node m(YAML::NodeType::Map);
  auto color = [&](const std::string& name, glm::dvec3 fallback) {
    ColorParam c = colorParam(ps, name, fallback);
    if (c.textured) warn(at, "a texture for \"" + name + "\": textures not supported yet by the pbrt importer; its default used");
    if (!c.approximation.empty()) warn(at, c.approximation);
    return c.rgb;
  };
  auto albedo = [&](const std::string& name, glm::dvec3 fallback) {
    glm::dvec3 c = color(name, fallback);
    if (glm::any(glm::greaterThan(c, glm::dvec3(1))) || glm::any(glm::lessThan(c, glm::dvec3(0)))) {
      warn(at, "\"" + name + "\" outside [0, 1] clamped (lightbench's BSDFs conserve energy)");
      c = glm::clamp(c, 0.0, 1.0);
    }
    return flowVec(c);
  };
  // GGX alpha from roughness (import.h); lightbench's microfacets are isotropic.
  auto alphaOf = [&](const std::string& prefix) {
    double r = ps.getFloat(prefix + "roughness", 0);
    double u = ps.getFloat(prefix + "uroughness", r), v = ps.getFloat(prefix + "vroughness", r);
    if (u < 0 || v < 0) throw ConfigError(at.file, at.line, at.column, prefix + "roughness", "must not be negative");
    if (u != v) warn(at, "anisotropic roughness approximated by the mean of uroughness and vroughness");
    double alpha = (u + v) / 2;
    if (ps.getBool("remaproughness", true)) alpha = std::sqrt(alpha);
    if (alpha > 1) {
      warn(at, "a GGX alpha above 1 clamped to 1");
      alpha = 1;
    }
    return alpha;
  };
  auto roughness = [&](const std::string& prefix) {
    m["roughness"] = alphaOf(prefix);
    m["distribution"] = "ggx";
  };
  auto conductor = [&](const std::string& prefix) {
    m["type"] = "conductor";
    // coatedconductor names its metal conductor.eta and conductor.k, but its reflectance "reflectance".
    if (ps.has("reflectance")) {
      // pbrt-v4's artist-friendly form: eta 1 and the k whose normal-incidence
      // Fresnel reflectance is r, k = 2√r / √(1 − r).
      glm::dvec3 r = glm::clamp(color("reflectance", glm::dvec3(0)), 0.0, 0.9999);
      m["eta"] = 1.0;
      m["k"] = flowVec(2.0 * glm::sqrt(r) / glm::sqrt(1.0 - r));
    } else {
      m["eta"] = flowVec(color(prefix + "eta", *namedSpectrum("metal-Cu-eta")));
      m["k"] = flowVec(color(prefix + "k", *namedSpectrum("metal-Cu-k")));
    }
    roughness(prefix);
  };
  auto ior = [&](const std::string& name) {
    ColorParam c = colorParam(ps, name, glm::dvec3(1.5));
    if (c.textured) warn(at, "a textured eta not supported; 1.5 used");
    if (c.rgb.x != c.rgb.y || c.rgb.y != c.rgb.z) warn(at, "a dispersive eta approximated by its green value");
    double v = c.rgb.y;
    if (!(v > 0)) throw ConfigError(at.file, at.line, at.column, name, "an index of refraction must be positive");
    return v;
  };
  // pbrt-v4's bump and normal maps (materials.h: BumpMap, NormalMap) as
  // lightbench's (core/textures/surface_maps.h). The normal map is an image
  // of linear values, looked up at (u, 1 − v) like an imagemap.
  YAML::Node bump, normalMap;
  if (const Param* p = ps.find("displacement")) {
    if (p->type == "texture" && p->strings.size() == 1 && namedFloatTextures_.count(p->strings[0]))
      bump = namedFloatTextures_.at(p->strings[0]);
    else if (p->type != "float")
      warn(at, "parameter " + p->declaration() + ": an unknown texture; ignored");
    // A constant displacement moves the surface without turning it: nothing to do.
  }
  if (std::string file = ps.getString("normalmap", ""); !file.empty()) {
    normalMap = YAML::Node(YAML::NodeType::Map);
    normalMap["type"] = "image";
    normalMap["file"] = file;
    normalMap["srgb"] = false;
    YAML::Node flip(YAML::NodeType::Sequence);
    flip.SetStyle(YAML::EmitterStyle::Flow);
    for (double x : {1.0, 0.0, 0.0, 0.0, -1.0, 1.0}) flip.push_back(x);
    normalMap["uv_transform"] = flip;
  }
  const Param* refl = ps.find("reflectance");
  if (type == "diffuse" && refl && refl->type == "texture" && refl->strings.size() == 1 &&
      namedTextures_.count(refl->strings[0])) {
    m["type"] = "diffuse";
    m["albedo"] = 1.0;
    m["texture"] = namedTextures_.at(refl->strings[0]);
  } else if (type == "diffuse") {
    m["type"] = "diffuse";
    m["albedo"] = albedo("reflectance", glm::dvec3(0.5));
  } else if (type == "conductor") {
    conductor("");
  } else if (type == "dielectric" || type == "thindielectric") {
    m["type"] = type == "dielectric" ? "dielectric" : "thin_dielectric";
    m["ior"] = ior("eta");
    if (type == "dielectric") roughness("");
  } else if (type == "coateddiffuse" || type == "coatedconductor") {
    // pbrt-v4's layered BSDFs, its random walks included (core/bsdfs/layered.h).
    bool diffuse = type == "coateddiffuse";
    std::string coat = diffuse ? "" : "interface.";
    m["type"] = diffuse ? "coated_diffuse" : "coated_conductor";
    m["ior"] = ior(coat + "eta");
    roughness(coat);
    if (diffuse && refl && refl->type == "texture" && refl->strings.size() == 1 && namedTextures_.count(refl->strings[0])) {
      m["albedo"] = 1.0;
      m["texture"] = namedTextures_.at(refl->strings[0]);
    } else if (diffuse) {
      m["albedo"] = albedo("reflectance", glm::dvec3(0.5));
    } else {
      if (ps.has("reflectance")) {  // as conductor's artist-friendly form above
        glm::dvec3 r = glm::clamp(color("reflectance", glm::dvec3(0)), 0.0, 0.9999);
        m["conductor_eta"] = 1.0;
        m["conductor_k"] = flowVec(2.0 * glm::sqrt(r) / glm::sqrt(1.0 - r));
      } else {
        m["conductor_eta"] = flowVec(color("conductor.eta", *namedSpectrum("metal-Cu-eta")));
        m["conductor_k"] = flowVec(color("conductor.k", *namedSpectrum("metal-Cu-k")));
      }
      m["conductor_roughness"] = alphaOf("conductor.");
    }
    m["thickness"] = ps.getFloat("thickness", 0.01);
    m["max_depth"] = ps.getInt("maxdepth", 10);
    m["samples"] = ps.getInt("nsamples", 1);
    glm::dvec3 layerAlbedo = color("albedo", glm::dvec3(0));
    if (layerAlbedo != glm::dvec3(0))
      warn(at, "a scattering medium between the layers (albedo, g) not supported; the layer only absorbs, as with albedo 0");
    ps.find("g");
  } else if (type == "interface" || type == "none" || type.empty()) {
    interfaceNext_ = true;
    // No surface: rays pass straight through (a medium boundary in pbrt).
    m["type"] = "dielectric";
    m["ior"] = 1.0;
  } else if (type == "diffusetransmission") {
    warn(at, "diffuse transmission not supported; read as diffuse with its reflectance");
    m["type"] = "diffuse";
    m["albedo"] = albedo("reflectance", glm::dvec3(0.25));
    ps.markAllUsed();
  } else {
    warn(at, "material '" + type + "' not supported; read as diffuse 0.5");
    ps.markAllUsed();
    m["type"] = "diffuse";
    m["albedo"] = 0.5;
  }
  // As pbrt-v4 (GetBSDF): a displacement wins over a normal map.
  if (!bump.IsNull()) m["bump_map"] = bump;
  else if (!normalMap.IsNull()) m["normal_map"] = normalMap;
  ps.find("type");
  warnUnused(ps, at);
  return m;
}

}  // namespace lb::pbrt
