#include "core/mitsuba/bsdfs.h"
#include "core/bsdfs/named_conductors.h"
#include "core/mitsuba/translator.h"
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>

namespace lb::mitsuba {

namespace {

// Mitsuba's named indices of refraction (the table of its dielectric plugin's
// documentation, after Hecht's "Optics").
const std::map<std::string, double>& iorTable() {
  static const std::map<std::string, double> table = {
      {"vacuum", 1.0},          {"helium", 1.000036},        {"hydrogen", 1.000132},     {"air", 1.000277},
      {"carbon dioxide", 1.00045}, {"water", 1.3330},        {"acetone", 1.36},          {"ethanol", 1.361},
      {"carbon tetrachloride", 1.461}, {"glycerol", 1.4729}, {"benzene", 1.501},         {"silicone oil", 1.52045},
      {"bromine", 1.661},       {"water ice", 1.31},         {"fused quartz", 1.458},    {"pyrex", 1.470},
      {"acrylic glass", 1.49},  {"polypropylene", 1.49},     {"bk7", 1.5046},            {"sodium chloride", 1.544},
      {"amber", 1.55},          {"pet", 1.5750},             {"diamond", 2.419}};
  return table;
}

std::string lowercase(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

double iorProperty(XmlContext& xml, Props& p, pugi::xml_node n, const std::string& name, double fallback) {
  if (!p.has(name)) return fallback;
  std::string text = p.getText(name, "");  // a <string> names it, a <float> gives it
  double v = namedIor(text);
  if (v < 0) xml.fail(n, name, "unknown index of refraction '" + text + "' (a number, or e.g. bk7, water, air)");
  return v;
}

// Mitsuba's microfacet roughness: its distribution (Beckmann by default),
// alpha and separable Smith masking, all of which lightbench has; anisotropic
// alphas are averaged.
void microfacet(XmlContext& xml, Props& p, pugi::xml_node n, YAML::Node& m) {
  std::string distribution = lowercase(p.getString("distribution", "beckmann"));  // Mitsuba lowercases it
  double alpha = p.getFloat("alpha", 0.1);
  if (p.has("alpha_u") || p.has("alpha_v")) {
    double u = p.getFloat("alpha_u", alpha), v = p.getFloat("alpha_v", alpha);
    if (u != v) xml.warn(n, "anisotropic roughness is not supported; approximated as isotropic alpha = (alpha_u + alpha_v) / 2");
    alpha = (u + v) / 2;
  }
  p.getBool("sample_visible", true);  // how it samples, not what it estimates
  if (distribution != "ggx" && distribution != "beckmann")
    xml.fail(n, "distribution", "expected ggx or beckmann, got '" + distribution + "'");
  if (alpha > 1) {
    xml.warn(n, "alpha above 1 clamped to 1 (lightbench's microfacet distributions stop there)");
    alpha = 1;
  }
  m["roughness"] = alpha;
  m["distribution"] = distribution;
  m["masking"] = "separable";
}

YAML::Node conductor(XmlContext& xml, Props& p, pugi::xml_node n, bool rough) {
  YAML::Node m(YAML::NodeType::Map);
  m["type"] = "conductor";
  std::string material = p.getString("material", "none");
  if (material != "none") {
    if (const ComplexIor* metal = namedConductor(material)) {
      m["eta"] = flowVec(metal->eta);
      m["k"] = flowVec(metal->k);
    } else {
      xml.warn(n, "conductor material '" + material + "' is not in lightbench's table (Au, Ag, Cu, Al); approximated as a perfect mirror (material none)");
    }
  }
  if (p.has("eta")) m["eta"] = flowVec(p.getColor("eta", glm::dvec3(0.0)));
  if (p.has("k")) m["k"] = flowVec(p.getColor("k", glm::dvec3(1.0)));
  if (m["eta"] && !m["k"]) m["k"] = 0.0;
  if (p.has("ext_eta")) {
    // The exterior's index: Fresnel sees eta / ext_eta and k / ext_eta
    // (Mitsuba 0.6's conductor divides them so). A perfect mirror has none.
    double exterior = iorProperty(xml, p, n, "ext_eta", 1.0);
    if (!(exterior > 0)) xml.fail(n, "ext_eta", "an index of refraction must be positive");
    if (m["eta"]) {
      auto divided = [&](const char* key) {
        YAML::Node v = m[key];
        glm::dvec3 c = v.IsSequence() ? glm::dvec3(v[0].as<double>(), v[1].as<double>(), v[2].as<double>())
                                      : glm::dvec3(v.as<double>());
        m[key] = flowVec(c / exterior);
      };
      divided("eta"), divided("k");
    }
  }
  m["tint"] = flowVec(p.getColor("specular_reflectance", glm::dvec3(1.0)));
  if (rough) microfacet(xml, p, n, m);
  else m["roughness"] = 0.0;
  return m;
}

// int_ior over ext_ior (air by default), as every Mitsuba dielectric interface reads them.
double relativeIor(XmlContext& xml, Props& p, pugi::xml_node n, double interiorDefault) {
  double interior = iorProperty(xml, p, n, "int_ior", interiorDefault), exterior = iorProperty(xml, p, n, "ext_ior", 1.000277);
  if (!(interior > 0) || !(exterior > 0)) xml.fail(n, "int_ior", "indices of refraction must be positive");
  return interior / exterior;
}

YAML::Node dielectric(XmlContext& xml, Props& p, pugi::xml_node n, bool rough) {
  YAML::Node m(YAML::NodeType::Map);
  m["type"] = "dielectric";
  m["ior"] = relativeIor(xml, p, n, 1.5046);  // bk7
  for (const char* tint : {"specular_reflectance", "specular_transmittance"})
    if (p.has(tint) && p.getColor(tint, glm::dvec3(1.0)) != glm::dvec3(1.0))
      xml.warn(n, std::string(tint) + " is not supported on dielectrics; dropped (untinted)");
  if (rough) microfacet(xml, p, n, m);
  else m["roughness"] = 0.0;
  return m;
}

// plastic and roughplastic: core/bsdfs/plastic.h is Mitsuba's model.
YAML::Node plastic(XmlContext& xml, Props& p, pugi::xml_node n, bool rough) {
  YAML::Node m(YAML::NodeType::Map);
  m["type"] = "plastic";
  m["ior"] = relativeIor(xml, p, n, 1.49);  // polypropylene
  m["albedo"] = flowVec(p.getColor("diffuse_reflectance", glm::dvec3(0.5)));
  m["specular"] = flowVec(p.getColor("specular_reflectance", glm::dvec3(1.0)));
  m["nonlinear"] = p.getBool("nonlinear", false);
  if (rough) microfacet(xml, p, n, m);
  else m["roughness"] = 0.0;
  return m;
}

}  // namespace

double namedIor(const std::string& name) {
  char* end = nullptr;
  double v = std::strtod(name.c_str(), &end);
  if (end != name.c_str() && *end == '\0') return std::isfinite(v) ? v : -1;
  auto it = iorTable().find(lowercase(name));  // Mitsuba's lookup_ior lowercases
  return it == iorTable().end() ? -1 : it->second;
}

YAML::Node translateBsdf(XmlContext& xml, pugi::xml_node n, bool twoSided,
                         const std::map<std::string, pugi::xml_node>& ids) {
  const std::string type = xml.attr(n, "type");
  Props p(xml, n);
  // Nested textures and refs, by the property they give.
  std::map<std::string, pugi::xml_node> textures;
  for (pugi::xml_node o : p.objects) {
    std::string tag = o.name();
    if ((tag == "texture" || tag == "ref") && o.attribute("name")) textures[xml.propertyName(o)] = o;
    else xml.warn(o, "not supported inside a <bsdf>; dropped");
  }
  // The property lightbench can texture: f is linear in it (material.h).
  std::string textured;
  YAML::Node m;
  bool reflectsOnly = true;
  if (type == "diffuse") {
    // 0.x's diffuseReflectance is diffuse's reflectance (Mitsuba 3's upgrade_tree).
    const char* key = xml.oldDialect && (p.has("diffuse_reflectance") || textures.count("diffuse_reflectance"))
                          ? "diffuse_reflectance" : "reflectance";
    m = YAML::Node(YAML::NodeType::Map);
    m["type"] = "diffuse";
    m["albedo"] = flowVec(p.getColor(key, glm::dvec3(0.5)));
    textured = key;
  } else if (type == "conductor" || type == "roughconductor") {
    m = conductor(xml, p, n, type == "roughconductor");
    textured = "specular_reflectance";
  } else if (type == "dielectric" || type == "roughdielectric") {
    m = dielectric(xml, p, n, type == "roughdielectric");
    reflectsOnly = false;
  } else if (type == "thindielectric") {
    m = dielectric(xml, p, n, false);
    m["type"] = "thin_dielectric";
    m.remove("roughness");
    reflectsOnly = false;
  } else if (type == "roughdiffuse") {
    // Oren–Nayar as Mitsuba 0.6 evaluates it (core/bsdfs/rough_diffuse.h).
    const char* key = p.has("diffuse_reflectance") || textures.count("diffuse_reflectance") ? "diffuse_reflectance" : "reflectance";
    m = YAML::Node(YAML::NodeType::Map);
    m["type"] = "rough_diffuse";
    m["albedo"] = flowVec(p.getColor(key, glm::dvec3(0.5)));
    m["roughness"] = p.getFloat("alpha", 0.2);
    m["fast_approximation"] = p.getBool("use_fast_approx", false);
    textured = key;
  } else if (type == "plastic" || type == "roughplastic") {
    m = plastic(xml, p, n, type == "roughplastic");
    textured = "diffuse_reflectance";
  } else {
    xml.warn(n, "BSDF '" + type + "' not supported yet; approximated as diffuse with reflectance 0.5");
    p.takeAll();
    reflectsOnly = false;  // already said: no second warning about its sides
    m = YAML::Node(YAML::NodeType::Map);
    m["type"] = "diffuse";
    m["albedo"] = 0.5;
  }
  for (auto& [property, node] : textures) {
    if (property != textured) {
      xml.warn(node, "a texture on '" + property + "' of <bsdf type=\"" + type + "\"> is not supported; dropped (its constant default is used)");
      continue;
    }
    YAML::Node t = translateTexture(xml, node, ids);
    if (!t || t.IsNull()) continue;  // unsupported: warned, dropped
    m["texture"] = t;
    m[m["type"].as<std::string>() == "conductor" ? "tint" : "albedo"] = 1.0;  // the texture is the whole colour
  }
  // lightbench's reflecting BSDFs reflect on both sides (core/bsdfs/diffuse.h, conductor.h).
  if (!twoSided && reflectsOnly) xml.warn(n, "one-sided in Mitsuba (black from the back); rendered two-sided");
  p.finish();
  return m;
}

}  // namespace lb::mitsuba
