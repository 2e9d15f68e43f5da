#pragma once
// Reading Mitsuba XML the way Params reads YAML: positions (file:line) for
// every message, $parameter substitution, typed properties, and one warning
// per kind of unsupported element. The translation into a lightbench scene is
// in import.cpp; this file knows nothing of what the elements mean.
#include <pugixml.hpp>
#include <glm/glm.hpp>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>
#include "core/mitsuba/import.h"

namespace lb::mitsuba {

class XmlContext {
 public:
  XmlContext(const std::string& text, std::string path);

  // 1-based line of a byte offset (pugixml reports offsets, not lines).
  int lineAt(ptrdiff_t offset) const;
  int lineOf(pugi::xml_node n) const { return lineAt(n.offset_debug()); }
  // <tag type="...">, as messages name an element.
  std::string describe(pugi::xml_node n) const;
  [[noreturn]] void fail(pugi::xml_node n, const std::string& key, const std::string& message) const;
  // One warning per kind (element and message); later ones add their lines.
  void warn(pugi::xml_node n, const std::string& message);
  std::vector<ImportWarning> warnings() const;

  // The 0.5/0.6 dialect: property names are camelCase.
  bool oldDialect = false;
  // <default name="spp" value="64"/>: the first definition of a name wins.
  void addDefault(const std::string& name, const std::string& value);
  // An attribute with every $name replaced by its default; an undefined one is an error.
  std::string attr(pugi::xml_node n, const char* name) const;
  // A property's name, in the 3.x spelling (snake_case).
  std::string propertyName(pugi::xml_node n) const;
  // Numbers separated by spaces or commas, each finite.
  std::vector<double> numbers(pugi::xml_node n, const char* attribute) const;
  glm::dvec3 vec3(pugi::xml_node n, const char* attribute) const;

  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::vector<size_t> lineStarts_;
  std::vector<std::pair<std::string, std::string>> defaults_;  // longest name first
  ImportWarnings warnings_;
};

// The properties of one element (<float name=...>, <rgb>, <transform>, ...),
// read by name like Params reads keys: whatever nobody asks for is warned
// about by finish(). Nested objects (bsdf, emitter, ref, film, ...) are left
// to the caller in `objects`.
class Props {
 public:
  Props(XmlContext& xml, pugi::xml_node node);
  bool has(const std::string& name) const { return byName_.count(name) > 0; }
  double getFloat(const std::string& name, double fallback);
  long getInt(const std::string& name, long fallback);
  bool getBool(const std::string& name, bool fallback);
  std::string getString(const std::string& name, const std::string& fallback);
  // The value as written, of a <string>, <float> or <integer> (an IOR is a number or a name).
  std::string getText(const std::string& name, const std::string& fallback);
  // rgb (1 or 3 values), a float, or a spectrum of one value: linear RGB.
  glm::dvec3 getColor(const std::string& name, glm::dvec3 fallback);
  glm::dvec3 getPoint(const std::string& name, glm::dvec3 fallback);
  // Identity when absent; a non-invertible result is an error.
  glm::dmat4 getTransform(const std::string& name);
  // Marks every property read, for an element the caller has warned about as a whole.
  void takeAll();
  // Marks one property read whatever its type (settings of how, not what).
  void ignore(const std::string& name) { used_.insert(name); }
  void finish();

  std::vector<pugi::xml_node> objects;

 private:
  pugi::xml_node take(const std::string& name, const std::vector<std::string>& tags);
  XmlContext& xml_;
  pugi::xml_node node_;
  std::map<std::string, pugi::xml_node> byName_;
  std::set<std::string> used_;
};

}  // namespace lb::mitsuba
