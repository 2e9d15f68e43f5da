// pbrt-v4 scene file → lightbench scene description: the directive loop,
// transforms, attributes, named coordinate systems, Include and instancing
// (see import.h for the conventions and translator.h for the parts).
#include "core/pbrt/import.h"
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <algorithm>
#include <cmath>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>
#include "core/error.h"
#include "core/pbrt/translator.h"

namespace lb {

bool isPbrtPath(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".pbrt";
}

namespace pbrt {
namespace {

constexpr uintmax_t kMaxFileBytes = uintmax_t(256) << 20;
constexpr int kMaxIncludeDepth = 16;
constexpr int kMaxIncludedFiles = 10000;  // a file included twice per level would otherwise double 16 times
constexpr size_t kMaxAttributeDepth = 4096;

std::string readFile(const std::string& path, const std::string& from, int line, int column) {
  std::error_code ec;
  uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw ConfigError(from, line, column, "", "cannot read '" + path + "': " + ec.message());
  if (size > kMaxFileBytes) throw ConfigError(from, line, column, "", "'" + path + "' is larger than 256 MiB");
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  if (!in) throw ConfigError(from, line, column, "", "cannot read '" + path + "'");
  return ss.str();
}

std::string inQuotes(const std::string& s) { return "\"" + s + "\""; }

}  // namespace

Translator::Translator(std::string mainPath) : mainPath_(std::move(mainPath)) {
  folder_ = std::filesystem::path(mainPath_).parent_path().string();
}

void Translator::warn(const Where& at, const std::string& message) {
  std::string element = at.element;
  if (at.file != mainPath_) element += " (" + at.file + ":" + std::to_string(at.line) + ")";
  warnings_.add(at.element, element, at.mainLine, message);
}

void Translator::warnUnused(const ParamSet& ps, const Where& at) {
  for (const Param* p : ps.unused()) warn(at, "parameter " + p->declaration() + " not supported; ignored");
}

ImportedScene Translator::run(const std::string& text) {
  Tokenizer tokens(text, mainPath_);
  parse(tokens, 0, 0);
  if (!attributeStack_.empty()) throw ConfigError(mainPath_, 0, "", "end of file inside AttributeBegin (missing AttributeEnd)");
  if (!currentObject_.empty()) throw ConfigError(mainPath_, 0, "", "end of file inside ObjectBegin \"" + currentObject_ + "\"");
  if (!cameraSeen_) {
    // pbrt-v4's default: a perspective camera at the origin looking down +z, fov 90.
    gs_.ctm = glm::dmat4(1.0);
    camera("perspective", ParamSet{}, Where{mainPath_, 0, 0, 0, "Camera"});
  }
  if (!filmSeen_) film("rgb", ParamSet{}, Where{mainPath_, 0, 0, 0, "Film"});
  if (!filterSeen_) pixelFilter("gaussian", ParamSet{}, Where{mainPath_, 0, 0, 0, "PixelFilter"});
  if (!samplerSeen_) sampler("zsobol", ParamSet{}, Where{mainPath_, 0, 0, 0, "Sampler"});  // pbrt-v4's default
  if (!integratorSeen_) integrator("volpath", ParamSet{}, Where{mainPath_, 0, 0, 0, "Integrator"});
  root_["film"]["filter"] = filter_;
  // pbrt-v4's SPPM traces one photon per pixel per iteration unless told.
  if (root_["integrator"]["name"].as<std::string>() == "sppm" && !root_["integrator"]["photons_per_pass"])
    root_["integrator"]["photons_per_pass"] = root_["film"]["width"].as<long>() * root_["film"]["height"].as<long>();
  if (materials_.size()) root_["materials"] = materials_;
  for (const auto& [name, shapes] : objects_)
    if (shapes.size()) root_["objects"][name] = shapes;
  root_["shapes"] = shapes_;
  if (lights_.size()) root_["lights"] = lights_;
  out_.scene = root_;
  out_.warnings = warnings_.list();
  return out_;
}

void Translator::parse(Tokenizer& tokens, int includeDepth, int mainLine) {
  for (;;) {
    Token t = tokens.next();
    if (t.kind == Token::Kind::End) return;
    if (t.kind != Token::Kind::Word)
      tokens.fail(t, "expected a directive (e.g. Shape, LookAt), got " + (t.kind == Token::Kind::String ? inQuotes(t.text) : t.text));
    directive(t, tokens, includeDepth, includeDepth == 0 ? t.line : mainLine);
  }
}

void Translator::include(const Token& d, Tokenizer& tokens, int includeDepth, int mainLine) {
  Token name = tokens.next();
  if (name.kind != Token::Kind::String) tokens.fail(name, d.text + " expects a quoted file name");
  if (includeDepth + 1 > kMaxIncludeDepth)
    tokens.fail(d, d.text + " nested more than " + std::to_string(kMaxIncludeDepth) + " deep (does a file include itself?)");
  std::filesystem::path p(name.text);
  if (p.is_relative()) p = std::filesystem::path(folder_) / p;
  if (name.text.size() > 3 && name.text.compare(name.text.size() - 3, 3, ".gz") == 0)
    tokens.fail(name, "gzip-compressed scene files are not supported; decompress '" + name.text + "'");
  if (++includedFiles_ > kMaxIncludedFiles)
    tokens.fail(d, "more than " + std::to_string(kMaxIncludedFiles) + " files included in all");
  std::string text = readFile(p.string(), tokens.file(), name.line, name.column);
  Tokenizer inner(text, p.string());
  // Import (pbrt-v4's parallel Include) reads the same for a serial parser.
  parse(inner, includeDepth + 1, mainLine);
}

void Translator::directive(const Token& d, Tokenizer& tokens, int includeDepth, int mainLine) {
  const std::string& name = d.text;
  Where at{tokens.file(), d.line, d.column, mainLine, name};
  auto number = [&]() {
    Token t = tokens.next();
    double v = 0;
    if (t.kind != Token::Kind::Word || !parseNumber(t.text, v))
      tokens.fail(t, name + " expects numbers, got " + (t.kind == Token::Kind::End ? "the end of the file" : inQuotes(t.text)));
    return v;
  };
  auto numbers = [&](int n) {
    std::vector<double> v;
    for (int i = 0; i < n; ++i) v.push_back(number());
    return v;
  };
  auto bracketed16 = [&]() {
    Token open = tokens.next();
    if (open.kind != Token::Kind::OpenBracket) tokens.fail(open, name + " expects [ 16 numbers ]");
    std::vector<double> v = numbers(16);
    Token close = tokens.next();
    if (close.kind != Token::Kind::CloseBracket) tokens.fail(close, name + " expects [ 16 numbers ]: missing ']'");
    // Column by column, as glm stores a matrix.
    glm::dmat4 m = glm::make_mat4(v.data());
    if (m[0][3] != 0 || m[1][3] != 0 || m[2][3] != 0 || m[3][3] != 1)
      tokens.fail(open, name + ": a projective matrix (its fourth row, numbers 4, 8, 12, 16, must be 0 0 0 1)");
    return m;
  };
  auto string = [&](const char* what) {
    Token t = tokens.next();
    if (t.kind != Token::Kind::String) tokens.fail(t, name + " expects a quoted " + what);
    return t.text;
  };
  auto typed = [&](const char* what) {
    std::string type = string(what);
    at.element = name + " " + inQuotes(type);
    return type;
  };
  auto needWorld = [&](bool world) {
    if (world != inWorld_)
      tokens.fail(d, name + (world ? " is only allowed after WorldBegin" : " is only allowed before WorldBegin"));
  };
  auto notInObject = [&]() {
    if (!currentObject_.empty()) tokens.fail(d, name + " is not allowed inside ObjectBegin/ObjectEnd");
  };

  // A transform that overflowed (LookAt or Scale near 1e308) is refused here,
  // at its line, not as a non-finite number in the translation.
  auto checkFinite = [&]() {
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite(gs_.ctm[c][r])) tokens.fail(d, name + ": the transformation matrix is no longer finite");
  };
  if (name == "Translate") {
    std::vector<double> v = numbers(3);
    gs_.ctm = glm::translate(gs_.ctm, glm::dvec3(v[0], v[1], v[2]));
  } else if (name == "Scale") {
    std::vector<double> v = numbers(3);
    gs_.ctm = glm::scale(gs_.ctm, glm::dvec3(v[0], v[1], v[2]));
  } else if (name == "Rotate") {
    std::vector<double> v = numbers(4);
    glm::dvec3 axis(v[1], v[2], v[3]);
    if (glm::length(axis) == 0) tokens.fail(d, "Rotate about a zero axis");
    gs_.ctm = glm::rotate(gs_.ctm, glm::radians(v[0]), glm::normalize(axis));
  } else if (name == "LookAt") {
    std::vector<double> v = numbers(9);
    glm::dvec3 eye(v[0], v[1], v[2]), look(v[3], v[4], v[5]), up(v[6], v[7], v[8]);
    glm::dvec3 dir = look - eye;
    if (glm::length(dir) == 0) tokens.fail(d, "LookAt: the eye and the point looked at are the same");
    dir = glm::normalize(dir);
    if (glm::length(up) == 0 || glm::length(glm::cross(glm::normalize(up), dir)) < 1e-9)
      tokens.fail(d, "LookAt: the up vector is zero or parallel to the view direction");
    // pbrt-v4 transform.cpp LookAt: camera +x = up × dir, +y = dir × x, +z = dir.
    glm::dvec3 right = glm::normalize(glm::cross(glm::normalize(up), dir)), newUp = glm::cross(dir, right);
    glm::dmat4 worldFromCamera(glm::dvec4(right, 0), glm::dvec4(newUp, 0), glm::dvec4(dir, 0), glm::dvec4(eye, 1));
    gs_.ctm = gs_.ctm * glm::inverse(worldFromCamera);
  } else if (name == "Transform") {
    gs_.ctm = bracketed16();
  } else if (name == "ConcatTransform") {
    gs_.ctm = gs_.ctm * bracketed16();
  } else if (name == "Identity") {
    gs_.ctm = glm::dmat4(1.0);
  } else if (name == "CoordinateSystem") {
    namedCoordinateSystems_[string("name")] = gs_.ctm;
  } else if (name == "CoordSysTransform") {
    std::string n = string("name");
    auto it = namedCoordinateSystems_.find(n);
    if (it == namedCoordinateSystems_.end()) warn(at, "unknown coordinate system '" + n + "'; the transform is unchanged");
    else gs_.ctm = it->second;
  } else if (name == "TransformBegin" || name == "AttributeBegin") {
    attributeStack_.emplace_back(name == "TransformBegin" ? 't' : 'a', gs_);
    if (attributeStack_.size() > kMaxAttributeDepth) tokens.fail(d, name + " nested too deep");
  } else if (name == "TransformEnd" || name == "AttributeEnd") {
    char kind = name == "TransformEnd" ? 't' : 'a';
    if (attributeStack_.empty()) tokens.fail(d, name + " without " + (kind == 't' ? "TransformBegin" : "AttributeBegin"));
    if (attributeStack_.back().first != kind)
      tokens.fail(d, name + " where the innermost open block is " +
                         (attributeStack_.back().first == 'o' ? "ObjectBegin" : attributeStack_.back().first == 't' ? "TransformBegin" : "AttributeBegin") +
                         " (mismatched nesting)");
    gs_ = attributeStack_.back().second;
    attributeStack_.pop_back();
  } else if (name == "ReverseOrientation") {
    gs_.reverseOrientation = !gs_.reverseOrientation;
  } else if (name == "ActiveTransform") {
    Token t = tokens.next();
    if (t.kind != Token::Kind::Word || (t.text != "All" && t.text != "StartTime" && t.text != "EndTime"))
      tokens.fail(t, "ActiveTransform expects All, StartTime or EndTime");
    if (t.text != "All") warn(at, "motion blur not supported; transforms apply at all times");
  } else if (name == "TransformTimes") {
    numbers(2);
    warn(at, "motion blur not supported; ignored");
  } else if (name == "Attribute") {
    string("target (shape, light, material, medium or texture)");
    ParamSet::parse(tokens).markAllUsed();
    warn(at, "default parameters by Attribute not supported; ignored");
  } else if (name == "Include") {
    include(d, tokens, includeDepth, mainLine);
  } else if (name == "Import") {
    // pbrt-v4 imports a file's definitions (named materials, textures,
    // objects, shapes) but not its graphics state, and only in the world.
    needWorld(true);
    GraphicsState saved = gs_;
    size_t depth = attributeStack_.size();
    include(d, tokens, includeDepth, mainLine);
    if (attributeStack_.size() != depth) tokens.fail(d, "the imported file leaves an AttributeBegin or TransformBegin open");
    gs_ = saved;
  } else if (name == "WorldBegin") {
    needWorld(false);
    inWorld_ = true;
    gs_.ctm = glm::dmat4(1.0);
    namedCoordinateSystems_["world"] = gs_.ctm;
  } else if (name == "WorldEnd") {
    // pbrt-v3's; pbrt-v4 ends the world at the end of the file.
  } else if (name == "Option" || name == "ColorSpace") {
    if (name == "ColorSpace") {
      std::string cs = typed("colour space");
      if (cs != "srgb") warn(at, "only sRGB; the colour space is ignored");
    } else {
      ParamSet ps = ParamSet::parse(tokens);
      ps.markAllUsed();
      if (!ps.params.empty()) warn(Where{at.file, at.line, at.column, at.mainLine, "Option " + ps.params[0].declaration()},
                                   "not supported; ignored");
    }
  } else if (name == "Camera" || name == "Film" || name == "Sampler" || name == "PixelFilter" || name == "Integrator" ||
             name == "Accelerator") {
    needWorld(false);
    std::string type = typed("type");
    ParamSet ps = ParamSet::parse(tokens);
    if (name == "Camera") {
      if (cameraSeen_) tokens.fail(d, "a second Camera: a scene has one");
      // The CTM here maps world to camera space; pbrt names its inverse "camera".
      namedCoordinateSystems_["camera"] = glm::inverse(gs_.ctm);
      camera(type, ps, at);
    } else if (name == "Film") {
      film(type, ps, at);
    } else if (name == "Sampler") {
      sampler(type, ps, at);
    } else if (name == "PixelFilter") {
      pixelFilter(type, ps, at);
    } else if (name == "Integrator") {
      integrator(type, ps, at);
    } else {
      ps.markAllUsed();
      warn(at, "lightbench always uses Embree's BVH; ignored");
    }
  } else if (name == "MakeNamedMaterial") {
    needWorld(true);
    std::string matName = string("material name");
    at.element = name + " " + inQuotes(matName);
    ParamSet ps = ParamSet::parse(tokens);
    std::string type = ps.getString("type", "");
    if (type.empty()) tokens.fail(d, "MakeNamedMaterial " + inQuotes(matName) + " has no \"string type\"");
    if (namedMaterials_.count(matName)) warn(at, "redefined; later shapes use the new definition");
    namedMaterials_[matName] = addMaterial(matName, material(type, ps, at));
  } else if (name == "Material") {
    needWorld(true);
    std::string type = typed("material type");
    ParamSet ps = ParamSet::parse(tokens);
    gs_.material = addMaterial(type, material(type, ps, at));
  } else if (name == "NamedMaterial") {
    needWorld(true);
    std::string matName = string("material name");
    auto it = namedMaterials_.find(matName);
    if (it == namedMaterials_.end()) tokens.fail(d, "NamedMaterial " + inQuotes(matName) + " is not defined (MakeNamedMaterial comes first)");
    gs_.material = it->second;
  } else if (name == "Texture") {
    needWorld(true);
    std::string texName = string("texture name");
    std::string texClass = string("texture class (spectrum or float)");
    std::string texType = typed("texture type");
    at.element = "Texture " + inQuotes(texName) + " " + inQuotes(texType);
    ParamSet ps = ParamSet::parse(tokens);
    YAML::Node t = texture(texClass, texType, ps, at);
    // pbrt-v4 keeps float and spectrum textures apart: one name may be both.
    if (!t.IsNull()) (texClass == "float" ? namedFloatTextures_ : namedTextures_)[texName] = t;
  } else if (name == "LightSource") {
    needWorld(true);
    notInObject();
    std::string type = typed("light type");
    ParamSet ps = ParamSet::parse(tokens);
    lightSource(type, ps, at);
  } else if (name == "AreaLightSource") {
    needWorld(true);
    std::string type = typed("area light type");
    ParamSet ps = ParamSet::parse(tokens);
    gs_.areaLight = areaLightSource(type, ps, at);
  } else if (name == "Shape") {
    needWorld(true);
    std::string type = typed("shape type");
    ParamSet ps = ParamSet::parse(tokens);
    shape(type, ps, gs_, at);
  } else if (name == "ObjectBegin") {
    needWorld(true);
    notInObject();
    currentObject_ = string("object name");
    if (objects_.count(currentObject_)) tokens.fail(d, "object " + inQuotes(currentObject_) + " defined twice");
    objects_[currentObject_] = YAML::Node(YAML::NodeType::Sequence);
    attributeStack_.emplace_back('o', gs_);
  } else if (name == "ObjectEnd") {
    if (currentObject_.empty()) tokens.fail(d, "ObjectEnd without ObjectBegin");
    if (attributeStack_.empty() || attributeStack_.back().first != 'o')
      tokens.fail(d, "ObjectEnd inside an open AttributeBegin or TransformBegin (mismatched nesting)");
    currentObject_.clear();
    gs_ = attributeStack_.back().second;
    attributeStack_.pop_back();
  } else if (name == "ObjectInstance") {
    needWorld(true);
    notInObject();
    std::string obj = string("object name");
    if (!objects_.count(obj)) tokens.fail(d, "ObjectInstance of an undefined object " + inQuotes(obj));
    // pbrt-v4: instance-to-world is the CTM here, applied after each shape's
    // own CTM inside ObjectBegin. An object whose shapes were all dropped
    // (unsupported) has nothing to place.
    if (glm::determinant(glm::dmat3(gs_.ctm)) < 0)
      warn(at, "an instance under a mirroring transform: its triangles without normals turn over (lightbench's winding "
               "rule for a flattened mesh), where pbrt-v4 keeps their side");
    if (objects_.at(obj).size()) {
      YAML::Node s(YAML::NodeType::Map);
      s["type"] = "instance";
      s["object"] = obj;
      s["transform"]["matrix"] = rowMajor(gs_.ctm);
      out_.origins.emplace_back("shapes[" + std::to_string(shapes_.size()) + "]", at.mainLine);
      shapes_.push_back(s);
    }
  } else if (name == "MakeNamedMedium") {
    string("medium name");
    ParamSet::parse(tokens).markAllUsed();
    warn(at, "participating media not supported yet (issue 38); dropped");
  } else if (name == "MediumInterface") {
    string("medium name");
    if (tokens.peek().kind == Token::Kind::String) tokens.next();
    warn(at, "participating media not supported yet (issue 38); ignored");
  } else {
    static const char* known[] = {"Translate", "Scale", "Rotate", "LookAt", "Transform", "ConcatTransform", "Identity",
                                  "CoordinateSystem", "CoordSysTransform", "AttributeBegin", "AttributeEnd", "Shape",
                                  "Material", "MakeNamedMaterial", "NamedMaterial", "LightSource", "AreaLightSource",
                                  "Camera", "Film", "Sampler", "PixelFilter", "Integrator", "WorldBegin", "Include",
                                  "ObjectBegin", "ObjectEnd", "ObjectInstance", "Texture", "ReverseOrientation"};
    std::string hint;
    for (const char* k : known) {
      std::string a = k, b = name;
      std::transform(a.begin(), a.end(), a.begin(), ::tolower);
      std::transform(b.begin(), b.end(), b.begin(), ::tolower);
      if (a == b) hint = std::string("; did you mean '") + k + "'? (directives are case-sensitive)";
    }
    tokens.fail(d, "unknown directive '" + name + "'" + hint);
  }
  checkFinite();
}

}  // namespace pbrt

ImportedScene importPbrtFromString(const std::string& text, const std::string& virtualPath) {
  return pbrt::Translator(virtualPath).run(text);
}

ImportedScene importPbrt(const std::string& path) {
  return importPbrtFromString(pbrt::readFile(path, path, 0, 0), path);
}

}  // namespace lb
