// Mitsuba XML → lightbench scene description. Each element's translation
// follows Mitsuba 3's own reading of it (plugin documentation and
// src/core/xml.cpp); where ours differs, a warning says how.
#include "core/mitsuba/import.h"
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include "core/error.h"
#include "core/mitsuba/bsdfs.h"
#include "core/mitsuba/translator.h"
#include "core/image_input.h"

namespace lb {

bool isMitsubaXmlPath(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".xml";
}

namespace mitsuba {
namespace {

// The largest scene file read (meshes live in files of their own).
constexpr uintmax_t kMaxXmlBytes = uintmax_t(64) << 20;

bool isElement(pugi::xml_node n) { return n.type() == pugi::node_element; }

// pugixml (Mitsuba 3's reader too) leaves an entity it does not know as
// literal text and ends no value at a bare '&', where XML 1.0 (section 4.1)
// makes both a fatal error. The raw text is scanned for them outside
// comments, CDATA sections, processing instructions and the DOCTYPE.
// Returns the offset of the first bad '&', or npos.
size_t firstUndefinedEntity(const std::string& text) {
  static const char* predefined[] = {"lt;", "gt;", "amp;", "apos;", "quot;"};
  auto skipTo = [&](size_t i, const char* open, const char* close) {
    if (text.compare(i, std::strlen(open), open) != 0) return i;
    size_t end = text.find(close, i + std::strlen(open));
    return end == std::string::npos ? text.size() : end + std::strlen(close);
  };
  for (size_t i = 0; i < text.size();) {
    if (text[i] == '<') {
      size_t j = skipTo(i, "<!--", "-->");
      if (j == i) j = skipTo(i, "<![CDATA[", "]]>");
      if (j == i) j = skipTo(i, "<?", "?>");
      if (j == i && text.compare(i, 9, "<!DOCTYPE") == 0) {
        size_t bracket = text.find_first_of("[>", i);
        j = bracket != std::string::npos && text[bracket] == '[' ? skipTo(bracket, "[", "]") : bracket;
        j = j == std::string::npos ? text.size() : text.find('>', j);
        j = j == std::string::npos ? text.size() : j + 1;
      }
      i = j == i ? i + 1 : j;
      continue;
    }
    if (text[i] != '&') {
      ++i;
      continue;
    }
    bool known = false;
    for (const char* name : predefined) known = known || text.compare(i + 1, std::strlen(name), name) == 0;
    if (!known && i + 2 < text.size() && text[i + 1] == '#') {
      size_t k = i + 2;
      bool hex = text[k] == 'x';
      if (hex) ++k;
      size_t digits = k;
      while (k < text.size() && (hex ? std::isxdigit(static_cast<unsigned char>(text[k])) : std::isdigit(static_cast<unsigned char>(text[k])))) ++k;
      known = k > digits && k < text.size() && text[k] == ';';
    }
    if (!known) return i;
    ++i;
  }
  return std::string::npos;
}

}  // namespace

MitsubaImport Translator::run() {
  pugi::xml_document doc;
  pugi::xml_parse_result parsed = doc.load_buffer(text_.data(), text_.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!parsed)
    throw ConfigError(xml_.path(), xml_.lineAt(parsed.offset), "", std::string("malformed XML: ") + parsed.description());
  pugi::xml_node scene = doc.document_element();
  if (std::string(scene.name()) != "scene")
    throw ConfigError(xml_.path(), xml_.lineOf(scene), "", "expected a <scene> root element (a Mitsuba scene file)");
  // pugixml takes a second root, and drops text after the first, without a
  // word; XML allows one root and nothing but comments after it. Read again
  // as a fragment, which keeps the top level's text, to find either.
  pugi::xml_document fragment;
  fragment.load_buffer(text_.data(), text_.size(), pugi::parse_default | pugi::parse_fragment, pugi::encoding_utf8);
  pugi::xml_node first = fragment.find_child([](pugi::xml_node n) { return n.type() == pugi::node_element; });
  for (pugi::xml_node top = first.next_sibling(); top; top = top.next_sibling())
    if (top.type() == pugi::node_element || top.type() == pugi::node_pcdata || top.type() == pugi::node_cdata)
      throw ConfigError(xml_.path(), xml_.lineOf(top), "",
                        std::string("content after </scene>") + (isElement(top) ? " (a second root <" + std::string(top.name()) + ">)" : "") +
                            ": an XML file has one root element");
  if (size_t bad = firstUndefinedEntity(text_); bad != std::string::npos) {
    size_t end = text_.find_first_of("; \t\n<&\"'", bad + 1);
    std::string ref = text_.substr(bad, end != std::string::npos && text_[end] == ';' ? end - bad + 1 : 1);
    throw ConfigError(xml_.path(), xml_.lineAt(ptrdiff_t(bad)), "",
                      ref == "&" ? "a bare '&' (write it as &amp;)"
                                 : "undefined entity '" + ref + "' (XML predefines only &lt; &gt; &amp; &apos; &quot;" +
                                       (text_.find("<!ENTITY") != std::string::npos
                                            ? "; entities declared in a DTD are not read)"
                                            : ")"));
  }

  // An attribute given twice in one element is not well-formed XML (XML 1.0,
  // 3.1, "Unique Att Spec"); pugixml keeps both and the first was read.
  struct DuplicateAttribute : pugi::xml_tree_walker {
    pugi::xml_node at;
    std::string name;
    bool for_each(pugi::xml_node& n) override {
      for (pugi::xml_attribute a = n.first_attribute(); a; a = a.next_attribute())
        for (pugi::xml_attribute b = a.next_attribute(); b; b = b.next_attribute())
          if (std::string(a.name()) == b.name()) {
            at = n, name = a.name();
            return false;
          }
      return true;
    }
  } duplicate;
  doc.traverse(duplicate);
  if (duplicate.at)
    throw ConfigError(xml_.path(), xml_.lineOf(duplicate.at), "",
                      "<" + std::string(duplicate.at.name()) + "> gives attribute '" + duplicate.name +
                          "' twice (XML allows each attribute once)");

  // <scene version="0.5.0"> or "3.0.0": below 2 the properties are camelCase.
  std::string version = scene.attribute("version").value();
  char* end = nullptr;
  long major = std::strtol(version.c_str(), &end, 10);
  if (version.empty() || end == version.c_str() || major < 0)
    xml_.fail(scene, "version", "expected a version such as \"3.0.0\" or \"0.6.0\", got '" + version + "'");
  xml_.oldDialect = major < 2;

  for (pugi::xml_node d : scene.children("default")) {
    std::string name = d.attribute("name").value();
    if (name.empty() || !d.attribute("value")) xml_.fail(d, "name", "a <default> needs a name and a value");
    xml_.addDefault(name, d.attribute("value").value());
  }
  // Textures are read where a BSDF refers to them (bsdfs.cpp). The scene's
  // own BSDFs are read first: a shape may refer to one defined further down,
  // as Mitsuba allows.
  for (pugi::xml_node t : scene.children("texture")) registerId(t);
  for (pugi::xml_node b : scene.children("bsdf")) readBsdf(b);
  // Shapegroups too, so that an instance may name one defined further down.
  for (pugi::xml_node g : scene.children("shape"))
    if (std::string(g.attribute("type").value()) == "shapegroup") readShapeGroup(g);
  for (pugi::xml_node c : scene.children()) {
    if (!isElement(c)) continue;
    std::string tag = c.name();
    if (tag == "default" || tag == "texture" || tag == "bsdf") continue;  // read above, or where referred to
    if (tag == "integrator") readIntegrator(c);
    else if (tag == "sensor") readSensor(c);
    else if (tag == "bsdf") readBsdf(c);
    else if (tag == "shape" && std::string(c.attribute("type").value()) == "shapegroup") continue;  // read above
    else if (tag == "shape") readShape(c);
    else if (tag == "emitter") readEmitter(c);
    else xml_.warn(c, "not supported; dropped");
  }
  if (!sensorSeen_) xml_.fail(scene, "sensor", "the scene has no <sensor type=\"perspective\">");
  if (!integratorSeen_) {
    YAML::Node integ(YAML::NodeType::Map);
    integ["name"] = "path";
    integ["max_depth"] = kUnlimitedDepth;
    root_["integrator"] = integ;
    out_.sharedIntegratorKeys.push_back("max_depth");
    xml_.warn(scene, "no <integrator>: Mitsuba's default path tracer, its unlimited max_depth approximated as " +
                         std::to_string(kUnlimitedDepth) + " segments");
  }
  if (materials_.size()) root_["materials"] = materials_;
  for (const auto& [id, shapes] : groups_)
    if (shapes.size()) root_["objects"][id] = shapes;
  root_["shapes"] = shapes_;
  if (lights_.size()) root_["lights"] = lights_;
  out_.scene = root_;
  out_.warnings = xml_.warnings();
  return out_;
}

void Translator::registerId(pugi::xml_node n) {
  if (!n.attribute("id")) return;
  std::string id = xml_.attr(n, "id");
  auto [it, fresh] = ids_.emplace(id, n);
  if (!fresh) xml_.fail(n, "id", "'" + id + "' is used twice (first on line " + std::to_string(xml_.lineOf(it->second)) + ")");
}

namespace {
// BSDFs that wrap another and add a surface map to it (Material::SurfaceMaps):
// the map's texture, by the property each plugin names it.
const std::map<std::string, std::pair<std::string, std::string>>& wrappers() {
  static const std::map<std::string, std::pair<std::string, std::string>> w = {
      {"bumpmap", {"map", "bump_map"}}, {"normalmap", {"normalmap", "normal_map"}}, {"mask", {"opacity", "opacity"}}};
  return w;
}
bool isWrapper(const std::string& type) { return wrappers().count(type) > 0; }
}  // namespace

// A wrapper (bumpmap, normalmap, mask) is the material it wraps with the map
// added: a copy of that material's YAML with `bump_map`, `normal_map` or
// `opacity`. A nested BSDF with an id of its own names the nested material
// alone, without the map: a <ref> to it gets what Mitsuba's would (staircase's
// bumpmap wraps a twosided BSDF that the shapes name, so they are not bumped).
std::string Translator::readWrapper(pugi::xml_node n, bool twoSided) {
  const std::string type = xml_.attr(n, "type");
  const auto& [property, key] = wrappers().at(type);
  Props p(xml_, n);
  pugi::xml_node nested, nestedRef, map;
  for (pugi::xml_node o : p.objects) {
    std::string tag = o.name();
    // A <ref> names the nested BSDF (one read before) or the map.
    bool refToBsdf = tag == "ref" && ids_.count(xml_.attr(o, "id")) &&
                     std::string(ids_.at(xml_.attr(o, "id")).name()) == "bsdf";
    if ((tag == "bsdf" || refToBsdf) && !nested && !nestedRef) (tag == "bsdf" ? nested : nestedRef) = o;
    else if ((tag == "texture" || tag == "ref") && !refToBsdf && !map && (type == "bumpmap" || xml_.propertyName(o) == property)) map = o;
    else xml_.warn(o, "not supported inside <bsdf type=\"" + type + "\">; dropped");
  }
  if (!nested && !nestedRef) xml_.fail(n, "", "a " + type + " BSDF needs a nested <bsdf>");
  std::string inner;
  if (nestedRef) {
    auto it = bsdfMaterial_.find(xml_.attr(nestedRef, "id"));
    if (it == bsdfMaterial_.end())
      xml_.fail(nestedRef, "id", "a " + type + " refers to a BSDF defined after it; define that BSDF first");
    inner = it->second;
  }
  // Mitsuba 3's bumpmap scales the height's gradient; a mask may give its
  // opacity as a number or a colour (its luminance).
  double scale = type == "bumpmap" ? p.getFloat("scale", 1.0) : 1.0;
  std::optional<glm::dvec3> uniformOpacity;
  if (type == "mask" && p.has("opacity")) uniformOpacity = p.getColor("opacity", glm::dvec3(0.5));
  p.finish();
  if (nested) inner = readBsdf(nested, twoSided);
  YAML::Node m = YAML::Clone(materials_[inner]);
  // Nothing else can name an anonymous nested BSDF: only this wrapper's copy stays.
  bool named = false;
  for (const auto& [id, material] : bsdfMaterial_) named |= material == inner;
  if (!named) {
    materials_.remove(inner);
    materialNames_.erase(inner);
  }
  // lightbench takes one of a normal and a bump map; Mitsuba applies both.
  for (const char* other : {"bump_map", "normal_map"})
    if (key != "opacity" && key != other && static_cast<const YAML::Node&>(m)[other]) {
      xml_.warn(n, std::string("a ") + type + " around a " + (std::string(other) == "bump_map" ? "bumpmap" : "normalmap") +
                       ": only the outer map is applied");
      m.remove(other);
      m.remove("bump_scale");
    }
  if (map) {
    YAML::Node t = translateTexture(xml_, map, ids_);
    if (t && !t.IsNull()) m[key] = t;
  } else if (uniformOpacity) {
    glm::dvec3 c = *uniformOpacity;
    m["opacity"] = std::clamp(0.212671 * c.x + 0.715160 * c.y + 0.072169 * c.z, 0.0, 1.0);
  } else if (type == "mask") {
    m["opacity"] = 0.5;  // Mitsuba's default
  } else {
    xml_.fail(n, property, "a " + type + " BSDF needs a texture '" + property + "'");
  }
  if (type == "bumpmap" && scale != 1.0) m["bump_scale"] = scale;
  return addMaterial(n, m);
}

// Names a translated BSDF (its id, or its line) and records it; errors in it
// are reported at `origin` (default: n).
std::string Translator::addMaterial(pugi::xml_node n, YAML::Node m, pugi::xml_node origin) {
  std::string id = n.attribute("id") ? xml_.attr(n, "id") : "";
  std::string name = id.empty() || id == "none" || materialNames_.count(id) ? "bsdf@L" + std::to_string(xml_.lineOf(n)) : id;
  materialNames_.insert(name);
  materials_[name] = m;
  this->origin("materials." + name, origin ? origin : n);
  if (!id.empty()) bsdfMaterial_[id] = name;
  return name;
}

// A named or inline BSDF becomes a material; returns its name. `twoSided`:
// it is nested in a twosided BSDF (said by the warning about one-sided ones).
std::string Translator::readBsdf(pugi::xml_node n, bool twoSided) {
  registerId(n);
  if (isWrapper(xml_.attr(n, "type"))) return readWrapper(n, twoSided);
  if (xml_.attr(n, "type") != "twosided") return addMaterial(n, translateBsdf(xml_, n, twoSided, ids_));
  Props p(xml_, n);
  std::vector<pugi::xml_node> nested;
  for (pugi::xml_node o : p.objects) {
    if (std::string(o.name()) == "bsdf") nested.push_back(o);
    else xml_.warn(o, "not supported inside <bsdf type=\"twosided\">; dropped");
  }
  p.finish();
  if (nested.empty()) xml_.fail(n, "", "a twosided BSDF needs a nested <bsdf>");
  if (nested.size() > 1) xml_.warn(nested[1], "a twosided BSDF's back-side BSDF is not supported; the front one is used on both sides");
  // A wrapper inside: its material is this one (lightbench's reflecting
  // BSDFs are two-sided already), named by both ids.
  if (isWrapper(xml_.attr(nested[0], "type"))) {
    std::string name = readBsdf(nested[0], true);
    if (n.attribute("id")) bsdfMaterial_[xml_.attr(n, "id")] = name;
    return name;
  }
  return addMaterial(n, translateBsdf(xml_, nested[0], true, ids_), nested[0]);
}

// A shapegroup's shapes become an object of the scene (`objects:`), each in
// the group's space; instances place it (Embree instancing, core/scene.h).
void Translator::readShapeGroup(pugi::xml_node n) {
  registerId(n);
  std::string id = xml_.attr(n, "id");
  if (id.empty()) xml_.fail(n, "id", "a shapegroup needs an id (its instances refer to it)");
  groups_[id] = YAML::Node(YAML::NodeType::Sequence);
  for (pugi::xml_node c : n.children()) {
    if (!isElement(c)) continue;
    std::string type = c.attribute("type").value();
    if (std::string(c.name()) != "shape" || type == "shapegroup")
      xml_.warn(c, "not supported inside <shape type=\"shapegroup\">; dropped");
    else
      readShape(c, id);
  }
}

// Mitsuba's instance: a <ref> to a shapegroup, placed by to_world (after
// each shape's own to_world inside the group).
void Translator::readInstance(pugi::xml_node n, Props& p, const glm::dmat4& toWorld, bool inGroup) {
  if (inGroup) xml_.fail(n, "type", "an instance inside a shapegroup (instancing is one level deep)");
  std::string group;
  for (pugi::xml_node o : p.objects) {
    if (std::string(o.name()) != "ref" || !group.empty()) {
      xml_.warn(o, "not supported inside <shape type=\"instance\">; dropped");
      continue;
    }
    group = xml_.attr(o, "id");
  }
  if (group.empty()) xml_.fail(n, "ref", "an instance needs a <ref> to a shapegroup");
  auto it = groups_.find(group);
  if (it == groups_.end())
    xml_.fail(n, "ref", ids_.count(group) ? "'" + group + "' is not a shapegroup" : "no shapegroup with id '" + group + "' in the scene");
  p.finish();
  if (glm::determinant(glm::dmat3(toWorld)) < 0)
    xml_.warn(n, "an instance under a mirroring transform: its triangles without normals turn over (lightbench's "
                 "winding rule for a flattened mesh), where Mitsuba keeps their side");
  if (!it->second.size()) return;  // every shape of the group was dropped
  YAML::Node s(YAML::NodeType::Map);
  s["type"] = "instance";
  s["object"] = group;
  s["transform"]["matrix"] = rowMajor(toWorld);
  origin("shapes[" + std::to_string(shapes_.size()) + "]", n);
  shapes_.push_back(s);
}

void Translator::readShape(pugi::xml_node n, const std::string& group) {
  registerId(n);
  std::string type = xml_.attr(n, "type");
  Props p(xml_, n);
  YAML::Node s(YAML::NodeType::Map);
  glm::dmat4 m = p.getTransform("to_world");
  if (type == "instance") return readInstance(n, p, m, !group.empty());
  bool flip = p.getBool("flip_normals", false);
  if (type == "rectangle" || type == "cube" || type == "disk") {
    // The same canonical shapes as lightbench's: [-1,1]² at z = 0 facing +z,
    // and [-1,1]³. A mirroring transform turns a triangle's winding (our
    // normal) but not Mitsuba's normal (M^-T n): flipped back here.
    s["type"] = type == "cube" ? "box" : type;
    if (type == "disk") xml_.warn(n, "disk approximated as a regular 256-sided polygon (area 0.01 % smaller)");
    YAML::Node t(YAML::NodeType::Map);
    t["matrix"] = rowMajor(m);
    s["transform"] = t;
    if ((glm::determinant(glm::dmat3(m)) < 0) != flip) s["flip_normals"] = true;
  } else if (type == "sphere") {
    glm::dvec3 center = p.getPoint("center", glm::dvec3(0.0));
    double radius = p.getFloat("radius", 1);
    double sx = glm::length(glm::dvec3(m[0])), sy = glm::length(glm::dvec3(m[1])), sz = glm::length(glm::dvec3(m[2]));
    if (std::abs(sx - sy) > 1e-6 * sx || std::abs(sx - sz) > 1e-6 * sx)
      xml_.fail(n, "to_world", "a sphere's transform must scale all axes alike");
    s["type"] = "sphere";
    s["center"] = flowVec(glm::dvec3(m * glm::dvec4(center, 1)));
    s["radius"] = radius * sx;
    if (flip) s["flip_normals"] = true;
    // lightbench's sphere has no frame of its own: its uv is about world z.
    glm::dmat3 r = glm::dmat3(m) / sx;
    if (glm::length(r[0] - glm::dvec3(1, 0, 0)) + glm::length(r[1] - glm::dvec3(0, 1, 0)) > 1e-6)
      xml_.warn(n, "a sphere's rotation is dropped (its shape is unchanged; a texture on it is laid out about world z)");
  } else if (type == "obj" || type == "ply") {
    // Mitsuba's face_normals: flat shading; otherwise the file's vertex
    // normals, or smooth ones computed when the file has none.
    s["type"] = "mesh";
    s["file"] = p.getString("filename", "");
    if (s["file"].as<std::string>().empty()) xml_.fail(n, "filename", "is required");
    YAML::Node t(YAML::NodeType::Map);
    t["matrix"] = rowMajor(m);
    s["transform"] = t;
    if (p.getBool("face_normals", false)) s["face_normals"] = true;
    else s["smooth_normals"] = true;
    if (flip) s["flip_normals"] = true;
    if (type == "obj" && !p.getBool("flip_tex_coords", true))
      xml_.warn(n, "flip_tex_coords false is not supported; texture coordinates are flipped (v = 1 - v), Mitsuba's default");
  } else {
    xml_.warn(n, "shape '" + type + "' not supported yet; dropped");
    p.takeAll();
    for (pugi::xml_node o : p.objects)  // its named BSDFs may be referenced later
      if (std::string(o.name()) == "bsdf") readBsdf(o);
    return;
  }
  YAML::Node& list = group.empty() ? shapes_ : groups_.at(group);
  const std::string key =
      (group.empty() ? std::string("shapes") : "objects." + group) + "[" + std::to_string(list.size()) + "]";
  bool hasBsdf = false, emitterSeen = false;
  for (pugi::xml_node o : p.objects) {
    std::string tag = o.name();
    std::string material;
    if (tag == "ref") {
      std::string id = xml_.attr(o, "id");
      auto it = bsdfMaterial_.find(id);
      if (it == bsdfMaterial_.end())
        xml_.fail(o, "id", ids_.count(id) ? "'" + id + "' is not a BSDF" : "no BSDF with id '" + id + "' in the scene");
      material = it->second;
    } else if (tag == "bsdf") {
      material = readBsdf(o);
    } else if (tag == "emitter") {
      if (emitterSeen) xml_.fail(o, "", "a second emitter in one shape (a shape emits through one area emitter)");
      emitterSeen = true;
      if (xml_.attr(o, "type") != "area") {
        xml_.warn(o, "only area emitters can be attached to a shape; dropped");
        continue;
      }
      Props e(xml_, o);
      glm::dvec3 radiance = e.getColor("radiance", glm::dvec3(1.0));
      for (pugi::xml_node eo : e.objects) xml_.warn(eo, "textured emitters are not supported yet; dropped");
      e.finish();
      if (!group.empty()) {
        xml_.warn(o, "an emitter inside a shapegroup: instances do not emit (as in pbrt-v4); dropped");
        continue;
      }
      // One-sided, on the normal's side, as Mitsuba's area emitter.
      s["emission"] = flowVec(radiance);
      continue;
    } else {
      xml_.warn(o, "not supported inside <shape>; dropped");
      continue;
    }
    if (hasBsdf) xml_.fail(o, "", "a shape can have only one BSDF");
    hasBsdf = true;
    s["material"] = material;
  }
  if (!hasBsdf) {
    xml_.warn(n, "no BSDF: Mitsuba's default (one-sided diffuse, reflectance 0.5) rendered two-sided");
    if (materialNames_.insert("mitsuba-default").second) {
      YAML::Node d(YAML::NodeType::Map);
      d["type"] = "diffuse";
      d["albedo"] = 0.5;
      materials_["mitsuba-default"] = d;
    }
    s["material"] = "mitsuba-default";
  }
  p.finish();
  origin(key, n);
  list.push_back(s);
}

void Translator::readEmitter(pugi::xml_node n) {
  registerId(n);
  std::string type = xml_.attr(n, "type");
  Props p(xml_, n);
  YAML::Node l(YAML::NodeType::Map);
  if (type == "point") {
    glm::dmat4 m = p.getTransform("to_world");
    glm::dvec3 position = p.getPoint("position", glm::dvec3(m[3]));
    l["type"] = "point";
    l["position"] = flowVec(position);
    l["intensity"] = flowVec(p.getColor("intensity", glm::dvec3(1.0)));
  } else if (type == "spot") {
    // Mitsuba's spot looks along its local +z from the origin of to_world.
    glm::dmat4 m = p.getTransform("to_world");
    glm::dvec3 position(m[3]), direction = glm::normalize(glm::dvec3(m[2]));
    double cutoff = p.getFloat("cutoff_angle", 20), beam = p.getFloat("beam_width", cutoff * 3 / 4);
    if (!(cutoff > 0 && cutoff < 180)) xml_.fail(n, "cutoff_angle", "must be in (0, 180) degrees");
    l["type"] = "spot";
    l["position"] = flowVec(position);
    l["look_at"] = flowVec(position + direction * std::max(1.0, glm::length(position)));
    l["intensity"] = flowVec(p.getColor("intensity", glm::dvec3(1.0)));
    l["cone_angle"] = cutoff;
    l["falloff_start"] = std::clamp(beam, 0.0, cutoff);
    if (beam < cutoff)
      xml_.warn(n, "the falloff between beam_width and cutoff_angle is linear in angle in Mitsuba, a smoothstep in "
                   "cos(angle) in lightbench (the same band)");
  } else if (type == "constant") {
    l["type"] = "environment";
    l["radiance"] = flowVec(p.getColor("radiance", glm::dvec3(1.0)));
  } else if (type == "envmap") {
    // The same lat-long convention as lightbench's map (+y up, u = 0 along
    // −z, v = 0 at the top row: environment_map_light.h); to_world turns it.
    std::string file = p.getString("filename", "");
    if (!isReadableImagePath(file)) {
      xml_.warn(n, "envmap '" + file + "': not an image format lightbench reads (EXR, HDR, PFM, PNG, JPEG, ...); the emitter is dropped");
      p.takeAll();
      p.finish();
      return;
    }
    l["type"] = "environment";
    l["file"] = file;
    l["scale"] = p.getFloat("scale", 1.0);
    glm::dmat3 r(p.getTransform("to_world"));
    glm::dmat3 e = glm::transpose(r) * r - glm::dmat3(1.0);
    double worst = 0;
    for (int i = 0; i < 3; ++i) worst = std::max({worst, std::abs(e[i].x), std::abs(e[i].y), std::abs(e[i].z)});
    if (!(worst < 1e-4)) xml_.fail(n, "to_world", "an envmap's to_world must be a rotation (no scale or shear)");
    YAML::Node rows(YAML::NodeType::Sequence);
    rows.SetStyle(YAML::EmitterStyle::Flow);
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 3; ++col) rows.push_back(r[col][row]);
    l["rotation"] = rows;
    xml_.warn(n, "envmap texels are looked up nearest, not bilinearly as in Mitsuba (sampling then follows the map exactly)");
    if (xml_.oldDialect) {
      double gamma = p.getFloat("gamma", 0);
      if (gamma != 0 && gamma != 1) xml_.warn(n, "envmap gamma is not supported; float files are linear, integer ones read as sRGB");
      p.getFloat("sampling_weight", 1);
      p.getBool("cache", false);
    }
    p.getBool("mis_compensation", false);  // how it samples, not what it estimates
  } else if (type == "directional") {
    glm::dmat4 m = p.getTransform("to_world");
    glm::dvec3 direction = p.has("direction") ? p.getPoint("direction", {}) : glm::dvec3(m * glm::dvec4(0, 0, 1, 0));
    l["type"] = "directional";
    l["direction"] = flowVec(direction);
    l["irradiance"] = flowVec(p.getColor("irradiance", glm::dvec3(1.0)));
  } else {
    xml_.warn(n, "emitter '" + type + "' not supported yet; dropped");
    p.takeAll();
    return;
  }
  for (pugi::xml_node o : p.objects) xml_.warn(o, "not supported inside <emitter>; dropped");
  p.finish();
  origin("lights[" + std::to_string(lights_.size()) + "]", n);
  lights_.push_back(l);
}

}  // namespace mitsuba

MitsubaImport importMitsubaXmlFromString(const std::string& xml, const std::string& virtualPath) {
  return mitsuba::Translator(xml, virtualPath).run();
}

MitsubaImport importMitsubaXml(const std::string& path) {
  std::error_code ec;
  uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw ConfigError(path, 0, "", "cannot open file");
  if (size > mitsuba::kMaxXmlBytes)
    throw ConfigError(path, 0, "", "scene file of " + std::to_string(size) + " bytes is larger than the 64 MiB read");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path, 0, "", "cannot open file");
  std::ostringstream text;
  text << in.rdbuf();
  return importMitsubaXmlFromString(text.str(), path);
}

}  // namespace lb
