#include "core/mitsuba/xml_reader.h"
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <glm/gtc/matrix_transform.hpp>
#include <sstream>
#include "core/error.h"

namespace lb::mitsuba {

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Mitsuba 3 reads 0.x files after renaming camelCase properties to snake_case
// (upgrade_tree in its xml.cpp): maxDepth → max_depth, toWorld → to_world.
std::string snakeCase(const std::string& name) {
  std::string out;
  for (size_t i = 0; i < name.size(); ++i) {
    unsigned char c = static_cast<unsigned char>(name[i]);
    if (std::isupper(c) && i > 0 && std::islower(static_cast<unsigned char>(name[i - 1]))) out += '_';
    out += char(std::tolower(c));
  }
  return out;
}

}  // namespace

XmlContext::XmlContext(const std::string& text, std::string path) : path_(std::move(path)) {
  lineStarts_.push_back(0);
  for (size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n') lineStarts_.push_back(i + 1);
}

int XmlContext::lineAt(ptrdiff_t offset) const {
  if (offset < 0) return 0;
  return int(std::upper_bound(lineStarts_.begin(), lineStarts_.end(), size_t(offset)) - lineStarts_.begin());
}

std::string XmlContext::describe(pugi::xml_node n) const {
  std::string type = n.attribute("type") ? " type=\"" + std::string(n.attribute("type").value()) + "\"" : "";
  return "<" + std::string(n.name()) + type + ">";
}

void XmlContext::fail(pugi::xml_node n, const std::string& key, const std::string& message) const {
  throw ConfigError(path_, lineOf(n), key.empty() ? describe(n) : describe(n) + "." + key, message);
}

void XmlContext::warn(pugi::xml_node n, const std::string& message) {
  warnings_.add(describe(n), describe(n), lineOf(n), message);
}

std::vector<ImportWarning> XmlContext::warnings() const {
  std::vector<ImportWarning> out = warnings_.list();
  // In file order (an element's unread properties are found after its children).
  std::stable_sort(out.begin(), out.end(), [](const ImportWarning& a, const ImportWarning& b) { return a.line < b.line; });
  return out;
}

void XmlContext::addDefault(const std::string& name, const std::string& value) {
  for (const auto& d : defaults_)
    if (d.first == name) return;
  defaults_.emplace_back(name, value);
  // Longest first, so that $spp does not eat the start of $spp_max.
  std::stable_sort(defaults_.begin(), defaults_.end(),
                   [](const auto& a, const auto& b) { return a.first.size() > b.first.size(); });
}

// One pass over the text: a default's value is not scanned again (a chain of
// defaults must not grow the string exponentially).
std::string XmlContext::attr(pugi::xml_node n, const char* name) const {
  const std::string v = n.attribute(name).value();
  if (v.find('$') == std::string::npos) return v;
  std::string out;
  for (size_t i = 0; i < v.size(); ++i) {
    if (v[i] != '$') {
      out += v[i];
      continue;
    }
    // Longest name first, so that $spp does not stop short of $spp_max.
    auto d = std::find_if(defaults_.begin(), defaults_.end(),
                          [&](const auto& kv) { return v.compare(i + 1, kv.first.size(), kv.first) == 0; });
    if (d == defaults_.end())
      fail(n, name, "undefined parameter '" + v.substr(i) + "' (no <default name=\"...\"> gives it)");
    out += d->second;
    i += d->first.size();
  }
  return out;
}

std::string XmlContext::propertyName(pugi::xml_node n) const {
  std::string name = attr(n, "name");
  return oldDialect ? snakeCase(name) : name;
}

std::vector<double> XmlContext::numbers(pugi::xml_node n, const char* attribute) const {
  std::string s = attr(n, attribute);
  for (char& c : s)
    if (c == ',') c = ' ';
  std::istringstream in(s);
  std::vector<double> out;
  for (std::string token; in >> token;) {
    char* end = nullptr;
    double v = std::strtod(token.c_str(), &end);
    if (end != token.c_str() + token.size() || !std::isfinite(v))
      fail(n, attribute, "expected finite numbers, got '" + token + "'");
    out.push_back(v);
  }
  return out;
}

glm::dvec3 XmlContext::vec3(pugi::xml_node n, const char* attribute) const {
  std::vector<double> v = numbers(n, attribute);
  if (v.size() != 3) fail(n, attribute, "expected 3 numbers");
  return {v[0], v[1], v[2]};
}

Props::Props(XmlContext& xml, pugi::xml_node node) : xml_(xml), node_(node) {
  static const std::set<std::string> propertyTags = {"float", "integer", "boolean", "string", "rgb", "srgb",
                                                      "spectrum", "point", "vector", "transform"};
  for (pugi::xml_node c : node.children()) {
    if (c.type() != pugi::node_element) continue;
    if (!propertyTags.count(c.name())) {
      objects.push_back(c);
      continue;
    }
    std::string name = xml.propertyName(c);
    if (name.empty()) xml.fail(c, "name", "a property needs a name");
    if (byName_.count(name))
      xml.fail(c, name, "given twice (first on line " + std::to_string(xml.lineOf(byName_[name])) + ")");
    byName_[name] = c;
  }
}

void Props::takeAll() {
  for (auto& kv : byName_) used_.insert(kv.first);
}

pugi::xml_node Props::take(const std::string& name, const std::vector<std::string>& tags) {
  auto it = byName_.find(name);
  if (it == byName_.end()) return {};
  used_.insert(name);
  if (std::find(tags.begin(), tags.end(), it->second.name()) == tags.end())
    xml_.fail(it->second, name, "expected <" + tags.front() + ">, got <" + it->second.name() + ">");
  return it->second;
}

double Props::getFloat(const std::string& name, double fallback) {
  pugi::xml_node n = take(name, {"float", "integer"});
  if (!n) return fallback;
  std::vector<double> v = xml_.numbers(n, "value");
  if (v.size() != 1) xml_.fail(n, name, "expected one number");
  return v[0];
}

long Props::getInt(const std::string& name, long fallback) {
  pugi::xml_node n = take(name, {"integer"});
  if (!n) return fallback;
  std::vector<double> v = xml_.numbers(n, "value");
  if (v.size() != 1 || v[0] != std::floor(v[0])) xml_.fail(n, name, "expected one integer");
  if (std::abs(v[0]) > 1e9) xml_.fail(n, name, "must be a whole number within ±1e9");
  return long(v[0]);
}

bool Props::getBool(const std::string& name, bool fallback) {
  pugi::xml_node n = take(name, {"boolean"});
  if (!n) return fallback;
  std::string v = lower(xml_.attr(n, "value"));
  if (v != "true" && v != "false") xml_.fail(n, name, "expected true or false, got '" + v + "'");
  return v == "true";
}

std::string Props::getString(const std::string& name, const std::string& fallback) {
  pugi::xml_node n = take(name, {"string"});
  return n ? xml_.attr(n, "value") : fallback;
}

std::string Props::getText(const std::string& name, const std::string& fallback) {
  pugi::xml_node n = take(name, {"string", "float", "integer"});
  return n ? xml_.attr(n, "value") : fallback;
}

// rgb (1 or 3 values), float, or a spectrum given as one value: linear RGB.
glm::dvec3 Props::getColor(const std::string& name, glm::dvec3 fallback) {
  pugi::xml_node n = take(name, {"rgb", "srgb", "spectrum", "float"});
  if (!n) return fallback;
  const std::string tag = n.name();
  if (tag == "spectrum" && xml_.attr(n, "value").find(':') != std::string::npos) {
    xml_.warn(n, "a sampled spectrum (wavelength:value pairs) is not supported; dropped, the default used");
    return fallback;
  }
  std::vector<double> v = xml_.numbers(n, "value");
  const bool rgb = tag == "rgb" || tag == "srgb";
  if (v.size() == 1) v = {v[0], v[0], v[0]};
  else if (v.size() != 3 || !rgb) xml_.fail(n, name, rgb ? "expected 1 or 3 numbers" : "expected one number");
  glm::dvec3 c(v[0], v[1], v[2]);
  // Mitsuba 0.x's <srgb>: sRGB-encoded, decoded to linear (IEC 61966-2-1).
  if (tag == "srgb")
    for (int i = 0; i < 3; ++i) c[i] = c[i] <= 0.04045 ? c[i] / 12.92 : std::pow((c[i] + 0.055) / 1.055, 2.4);
  return c;
}

glm::dvec3 Props::getPoint(const std::string& name, glm::dvec3 fallback) {
  pugi::xml_node n = take(name, {"point", "vector"});
  if (!n) return fallback;
  if (n.attribute("value")) return xml_.vec3(n, "value");
  glm::dvec3 p(0.0);
  const char* axes[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i)
    if (n.attribute(axes[i])) {
      std::vector<double> v = xml_.numbers(n, axes[i]);
      if (v.size() != 1) xml_.fail(n, axes[i], "expected one number");
      p[i] = v[0];
    }
  return p;
}

// Mitsuba's <transform>: each operation left-multiplies the ones before it
// (its xml.cpp: transform = op * transform), matrices are row-major.
glm::dmat4 Props::getTransform(const std::string& name) {
  pugi::xml_node t = take(name, {"transform"});
  glm::dmat4 m(1.0);
  if (!t) return m;
  for (pugi::xml_node op : t.children()) {
    if (op.type() != pugi::node_element) continue;
    std::string tag = lower(op.name());
    auto component = [&](const char* axis, double fallback) {
      if (!op.attribute(axis)) return fallback;
      std::vector<double> v = xml_.numbers(op, axis);
      if (v.size() != 1) xml_.fail(op, axis, "expected one number");
      return v[0];
    };
    glm::dmat4 step(1.0);
    if (tag == "matrix") {
      std::vector<double> v = xml_.numbers(op, "value");
      if (v.size() != 16 && v.size() != 9) xml_.fail(op, "value", "expected 16 (or 9) numbers, row by row");
      int n = v.size() == 16 ? 4 : 3;
      // A projective last row would be read as affine by whatever consumes it (the camera did).
      if (n == 4 && (v[12] != 0 || v[13] != 0 || v[14] != 0 || v[15] != 1))
        xml_.fail(op, "value", "the last row must be 0 0 0 1 (an affine transform)");
      for (int row = 0; row < n; ++row)
        for (int col = 0; col < n; ++col) step[col][row] = v[size_t(row * n + col)];
    } else if (tag == "translate" || tag == "scale") {
      double d = tag == "scale" ? 1 : 0;
      glm::dvec3 v(component("x", d), component("y", d), component("z", d));
      if (op.attribute("value")) {
        std::vector<double> u = xml_.numbers(op, "value");
        if (u.size() == 1 && tag == "scale") v = glm::dvec3(u[0]);
        else if (u.size() == 3) v = {u[0], u[1], u[2]};
        else xml_.fail(op, "value", "expected 3 numbers");
      }
      step = tag == "scale" ? glm::scale(glm::dmat4(1.0), v) : glm::translate(glm::dmat4(1.0), v);
    } else if (tag == "rotate") {
      glm::dvec3 axis(component("x", 0), component("y", 0), component("z", 0));
      if (op.attribute("value")) axis = xml_.vec3(op, "value");
      if (glm::length(axis) == 0) xml_.fail(op, "", "rotation axis is zero");
      step = glm::rotate(glm::dmat4(1.0), glm::radians(component("angle", 0)), glm::normalize(axis));
    } else if (tag == "lookat") {
      glm::dvec3 origin = xml_.vec3(op, "origin"), target = xml_.vec3(op, "target");
      glm::dvec3 up = op.attribute("up") ? xml_.vec3(op, "up") : glm::dvec3(0, 1, 0);
      glm::dvec3 dir = target - origin;
      if (glm::length(dir) == 0) xml_.fail(op, "target", "must differ from origin");
      dir = glm::normalize(dir);
      glm::dvec3 left = glm::cross(up, dir);
      if (glm::length(left) == 0) xml_.fail(op, "up", "must not be parallel to the view direction");
      left = glm::normalize(left);
      step = glm::dmat4(glm::dvec4(left, 0), glm::dvec4(glm::cross(dir, left), 0), glm::dvec4(dir, 0),
                        glm::dvec4(origin, 1));
    } else {
      // A dropped step would misplace everything after it: an error, not a warning.
      xml_.fail(op, "", "unsupported transform operation (matrix, translate, scale, rotate and lookat are)");
    }
    m = step * m;
  }
  const double d = glm::determinant(glm::dmat3(m));
  if (!(std::abs(d) > 0) || !std::isfinite(d)) xml_.fail(t, name, "the transform is not invertible");
  return m;
}

void Props::finish() {
  for (auto& [name, n] : byName_)
    if (!used_.count(name))
      xml_.warn(n, "property '" + std::string(n.attribute("name").value()) + "' of " + xml_.describe(node_) +
                       " not supported; dropped");
}

}  // namespace lb::mitsuba
