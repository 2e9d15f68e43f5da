#pragma once
// Typed, position-aware access to one YAML mapping. Every key that is read is
// recorded; checkUnused() then rejects any key nobody read, naming its line and
// the closest valid key ("did you mean"). Numbers must be finite.
#include <yaml-cpp/yaml.h>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>
#include "core/error.h"
#include "core/math.h"

namespace lb {

// The values a number may take, checked by the getter that reads it and
// printed by `lightbench integrators NAME`: one statement of the rule.
struct Range {
  double lo = -HUGE_VAL, hi = HUGE_VAL;
  bool loOpen = false, hiOpen = false;
  static Range atLeast(double lo) { return {lo, HUGE_VAL, false, false}; }
  static Range above(double lo) { return {lo, HUGE_VAL, true, false}; }
  static Range between(double lo, double hi) { return {lo, hi, false, false}; }  // [lo, hi]
  static Range openClosed(double lo, double hi) { return {lo, hi, true, false}; }  // (lo, hi]
  static Range open(double lo, double hi) { return {lo, hi, true, true}; }  // (lo, hi)
  bool contains(double v) const {
    return (loOpen ? v > lo : v >= lo) && (hiOpen ? v < hi : v <= hi);
  }
  bool bounded() const { return lo != -HUGE_VAL || hi != HUGE_VAL; }
  std::string text() const;  // "[0, 1]", ">= 1", "> 0"
  std::string violation() const;  // "must be positive", "must be in (0, 1)"
};

// What a key means (one line), and its range for numbers. The settings readers
// give it to the getters; the getters record it with the key's type and
// default, so the listing of an integrator's keys is the reader itself, run on
// an empty mapping (describeKeys below).
struct KeySpec {
  std::string meaning;
  Range range = {};
  // The allowed values as listed, when the range alone does not say them
  // (photon mapping's k: 0 or >= 2); the reader checks the rest itself.
  std::string allowed;
  KeySpec() = default;
  KeySpec(const char* m) : meaning(m) {}
  KeySpec(std::string m, Range r = {}, std::string a = "") : meaning(std::move(m)), range(r), allowed(std::move(a)) {}
};

// One key as read: name, type, default, allowed values, meaning.
struct KeyDoc {
  std::string key, type, fallback, allowed, meaning;
  std::string condition;  // when the key is read at all, e.g. "base: photon"; "" always
};

class Params {
 public:
  // `context` names the mapping in messages, e.g. "integrator" or "shapes[2]".
  Params(YAML::Node node, std::string file, std::string context);

  bool has(const std::string& key);
  float getFloat(const std::string& key, float fallback, const KeySpec& spec = {});
  float requireFloat(const std::string& key);
  int getInt(const std::string& key, int fallback, const KeySpec& spec = {});
  bool getBool(const std::string& key, bool fallback, const KeySpec& spec = {});
  std::string getString(const std::string& key, const std::string& fallback, const KeySpec& spec = {});
  std::string requireString(const std::string& key);
  // One of `choices`; anything else is an error listing them.
  std::string getChoice(const std::string& key, const std::string& fallback, const std::vector<std::string>& choices,
                        const KeySpec& spec = {});
  Vec3 getVec3(const std::string& key, Vec3 fallback);
  Vec3 requireVec3(const std::string& key);
  // Exactly `count` finite numbers.
  std::vector<float> getFloatList(const std::string& key, size_t count);
  // Any positive multiple of `multipleOf` finite numbers (inline mesh data);
  // empty if the key is absent.
  std::vector<float> getFloatSequence(const std::string& key, size_t multipleOf);
  // Colours also accept a single number (grey).
  Color getColor(const std::string& key, Color fallback);
  Color requireColor(const std::string& key);

  // Nested mapping or sequence of mappings; the children check their own keys.
  std::optional<Params> getChild(const std::string& key);
  std::vector<Params> getList(const std::string& key);

  // Throws for the first key that no get*/has call asked for, naming the
  // closest valid key and listing them all.
  void checkUnused() const;
  // Every key read so far, in reading order, with its spec.
  const std::vector<KeyDoc>& keyDocs() const { return docs_; }
  // True while a reader is run only to list its keys (describeKeys): readers
  // then read keys that depend on another key's value too.
  bool describing() const { return describing_; }
  // Keys read from now on are read only under `condition` (see KeyDoc).
  void setCondition(std::string condition) { condition_ = std::move(condition); }
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
  // A required key that is absent, or present misspelled: the misspelling named.
  [[noreturn]] void failMissing(const std::string& key) const;

  YAML::Node node_;
  std::string file_, context_;
  std::set<std::string> asked_, overridden_;
  std::vector<KeyDoc> docs_;
  bool describing_ = false;
  std::string condition_;
  void document(const std::string& key, const std::string& type, const std::string& fallback,
                const std::string& allowed, const std::string& meaning);
  void checkRange(const std::string& key, double v, const KeySpec& spec) const;
  friend std::vector<KeyDoc> describeKeys(const std::function<void(Params&)>& reader);
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

// The keys `reader` reads: it is run on an empty mapping in describing mode.
std::vector<KeyDoc> describeKeys(const std::function<void(Params&)>& reader);

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
