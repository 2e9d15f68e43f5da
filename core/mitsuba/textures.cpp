// Mitsuba textures as lightbench textures (core/textures/texture.h): bitmap
// and checkerboard, with Mitsuba's uv conventions (v = 0 at the image's top,
// OBJ texture coordinates flipped on load), so a texture lands where Mitsuba
// puts it. Anything else is warned about and dropped.
#include <cmath>
#include "core/mitsuba/bsdfs.h"
#include "core/mitsuba/translator.h"

namespace lb::mitsuba {

namespace {

// The uv map as lightbench's uv_transform [a b c; d e f]: Mitsuba 3's to_uv
// (a 4×4 transform whose 2-D part is the upper-left 2×2 and the translation's
// x, y), or 0.x's uscale, vscale, uoffset, voffset.
YAML::Node uvTransform(XmlContext& xml, Props& p) {
  double a = 1, b = 0, c = 0, d = 0, e = 1, f = 0;
  if (p.has("to_uv")) {
    glm::dmat4 m = p.getTransform("to_uv");  // glm: m[column][row]
    a = m[0][0], b = m[1][0], c = m[3][0], d = m[0][1], e = m[1][1], f = m[3][1];
  }
  if (xml.oldDialect) {
    double us = p.getFloat("uscale", 1), vs = p.getFloat("vscale", 1);
    double uo = p.getFloat("uoffset", 0), vo = p.getFloat("voffset", 0);
    a *= us, b *= us, c = c * us + uo, d *= vs, e *= vs, f = f * vs + vo;
  }
  YAML::Node t(YAML::NodeType::Sequence);
  t.SetStyle(YAML::EmitterStyle::Flow);
  for (double v : {a, b, c, d, e, f}) t.push_back(v);
  return t;
}

YAML::Node bitmap(XmlContext& xml, Props& p, pugi::xml_node n) {
  YAML::Node t(YAML::NodeType::Map);
  t["type"] = "image";
  t["file"] = p.getString("filename", "");
  if (t["file"].as<std::string>().empty()) xml.fail(n, "filename", "a bitmap needs a filename");
  bool srgb = !p.getBool("raw", false);
  if (xml.oldDialect && p.has("gamma")) {
    // 0.x: 0 = from the file, -1 = sRGB, 1 = linear, anything else a power law.
    double gamma = p.getFloat("gamma", 0);
    if (gamma == 1) srgb = false;
    else if (gamma != 0 && gamma != -1) xml.warn(n, "gamma other than sRGB (-1) or linear (1) is not supported; decoded as sRGB");
  }
  t["srgb"] = srgb;
  std::string filter = p.getString("filter_type", xml.oldDialect ? "ewa" : "bilinear");
  if (filter == "nearest") t["filter"] = "nearest";
  else {
    if (filter != "bilinear") xml.warn(n, "filter_type '" + filter + "' (mip-mapped) is not supported; approximated as bilinear");
    t["filter"] = "bilinear";
  }
  for (const char* wrap : {"wrap_mode", "wrap_mode_u", "wrap_mode_v"}) {
    std::string mode = p.getString(wrap, "repeat");
    if (mode != "repeat") xml.warn(n, std::string(wrap) + " '" + mode + "' is not supported; approximated as repeat");
  }
  for (const char* how : {"format", "accel", "cache", "max_anisotropy"}) p.ignore(how);  // how it is stored, not what
  t["uv_transform"] = uvTransform(xml, p);
  return t;
}

YAML::Node checkerboard(XmlContext& xml, Props& p) {
  YAML::Node t(YAML::NodeType::Map);
  t["type"] = "checkerboard";
  t["color0"] = flowVec(p.getColor("color0", glm::dvec3(0.4)));
  t["color1"] = flowVec(p.getColor("color1", glm::dvec3(0.2)));
  t["uv_transform"] = uvTransform(xml, p);
  return t;
}

}  // namespace

YAML::Node translateTexture(XmlContext& xml, pugi::xml_node n, const std::map<std::string, pugi::xml_node>& ids) {
  if (std::string(n.name()) == "ref") {
    std::string id = xml.attr(n, "id");
    auto it = ids.find(id);
    if (it == ids.end()) xml.fail(n, "id", "no element has id '" + id + "'");
    if (std::string(it->second.name()) != "texture") xml.fail(n, "id", "'" + id + "' is a <" + it->second.name() + ">, not a <texture>");
    return translateTexture(xml, it->second, ids);
  }
  std::string type = xml.attr(n, "type");
  Props p(xml, n);
  YAML::Node t;
  if (type == "bitmap") t = bitmap(xml, p, n);
  else if (type == "checkerboard") t = checkerboard(xml, p);
  else {
    xml.warn(n, "texture '" + type + "' is not supported; dropped (the BSDF's constant value, or its default, is used)");
    p.takeAll();
  }
  for (pugi::xml_node o : p.objects) xml.warn(o, "a texture inside a texture is not supported; dropped");
  p.finish();
  return t;
}

}  // namespace lb::mitsuba
