#pragma once
// Typed, position-aware access to one YAML mapping. Every key that is read is
// recorded; checkUnused() then rejects any key nobody read, naming its line and
// the closest valid key ("did you mean"). Numbers must be finite.
#include <yaml-cpp/yaml.h>
#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>
#include "core/error.h"
#include "core/math.h"

namespace lb {

class Params {
 public:
  // `context` names the mapping in messages, e.g. "integrator" or "shapes[2]".
  Params(YAML::Node node, std::string file, std::string context);

  bool has(const std::string& key);
  float getFloat(const std::string& key, float fallback);
  float requireFloat(const std::string& key);
  int getInt(const std::string& key, int fallback);
  bool getBool(const std::string& key, bool fallback);
  std::string getString(const std::string& key, const std::string& fallback);
  std::string requireString(const std::string& key);
  // One of `choices`; anything else is an error listing them.
  std::string getChoice(const std::string& key, const std::string& fallback, const std::vector<std::string>& choices);
  Vec3 getVec3(const std::string& key, Vec3 fallback);
  Vec3 requireVec3(const std::string& key);
  // Exactly `count` finite numbers.
  std::vector<float> getFloatList(const std::string& key, size_t count);
  // Colours also accept a single number (grey).
  Color getColor(const std::string& key, Color fallback);
  Color requireColor(const std::string& key);

  // Nested mapping or sequence of mappings; the children check their own keys.
  std::optional<Params> getChild(const std::string& key);
  std::vector<Params> getList(const std::string& key);

  // Throws for the first key that no get*/has call asked for.
  void checkUnused() const;
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;
  // The error fail() would throw, for checks made later (e.g. at render time).
  ConfigError error(const std::string& key, const std::string& message) const;

  int line(const std::string& key) const;
  int line() const { return node_.Mark().line >= 0 ? node_.Mark().line + 1 : 0; }
  const std::string& file() const { return file_; }
  const std::string& context() const { return context_; }
  const YAML::Node& node() const { return node_; }
  // Keys given on the command line (--set) are reported as such.
  void markOverridden(const std::string& key) { overridden_.insert(key); }
  // Every value read, defaults included: the fully resolved configuration.
  const YAML::Node& resolved() const { return resolved_; }

 private:
  YAML::Node lookup(const std::string& key);
  float toFloat(const YAML::Node& n, const std::string& key) const;
  Vec3 toVec3(const YAML::Node& n, const std::string& key, bool allowScalar) const;
  std::string qualified(const std::string& key) const;

  YAML::Node node_;
  std::string file_, context_;
  std::set<std::string> asked_, overridden_;
  YAML::Node resolved_{YAML::NodeType::Map};
  template <typename T>
  T record(const std::string& key, T value) {
    resolved_[key] = value;
    return value;
  }
  Vec3 recordVec3(const std::string& key, Vec3 v) {
    YAML::Node seq(YAML::NodeType::Sequence);
    seq.SetStyle(YAML::EmitterStyle::Flow);
    for (int i = 0; i < 3; ++i) seq.push_back(v[i]);
    resolved_[key] = seq;
    return v;
  }
};

// Closest candidate by edit distance, or "" if none is close.
std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates);

// The largest YAML file loadYamlFile reads (2 MiB: at most ~3 s and ~500 MB
// for yaml-cpp on the worst case, a dense flow list).
constexpr uintmax_t kMaxYamlBytes = uintmax_t(2) << 20;

// Loads a YAML file; malformed YAML becomes a ConfigError at the parser's line.
// The loaded document has passed checkMappings().
YAML::Node loadYamlFile(const std::string& path);
// Every mapping in `node`, at any depth: keys are plain scalars (not `[a, b]:`
// or `? {x: 1}`) and none is given twice (yaml-cpp keeps both silently).
// `context` prefixes the key paths in messages ("" at the top).
void checkMappings(const YAML::Node& node, const std::string& file, const std::string& context);
// The ConfigError for a document yaml-cpp could not parse (too deep nesting
// said as such, not as yaml-cpp's "bad file").
ConfigError malformedYaml(const std::string& file, const YAML::ParserException& e);

}  // namespace lb
