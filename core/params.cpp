#include "core/params.h"
#include <yaml-cpp/depthguard.h>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <iostream>

namespace lb {

void warn(const std::string& message) { std::cerr << "warning: " << message << "\n"; }

Params::Params(YAML::Node node, std::string file, std::string context)
    : node_(std::move(node)), file_(std::move(file)), context_(std::move(context)) {
  if (node_ && !node_.IsNull() && !node_.IsMap())
    throw ConfigError(file_, node_.Mark().line + 1, context_, "expected a mapping of key: value");
}

namespace {
// What a node is, for "expected X, got Y" messages.
std::string shapeOf(const YAML::Node& n) {
  if (n.IsSequence()) return "a sequence";
  if (n.IsMap()) return "a mapping";
  if (n.IsNull()) return "nothing";
  return "'" + n.Scalar() + "'";
}
// A mapping key as text; non-scalar keys (checked at load time) never match.
std::string keyText(const YAML::Node& k) { return k.IsScalar() ? k.Scalar() : std::string(); }
}  // namespace

std::string Params::qualified(const std::string& key) const {
  return context_.empty() ? key : context_ + "." + key;
}

int Params::line(const std::string& key) const {
  if (node_ && node_.IsMap())
    for (auto it = node_.begin(); it != node_.end(); ++it)
      if (keyText(it->first) == key) {
        // Keys of a rebuilt mapping (e.g. integrator parameters merged with
        // --set) have no position; their values keep the file's.
        int l = it->first.Mark().line >= 0 ? it->first.Mark().line : it->second.Mark().line;
        return l >= 0 ? l + 1 : line();
      }
  return line();
}

void Params::fail(const std::string& key, const std::string& message) const { throw error(key, message); }

ConfigError Params::error(const std::string& key, const std::string& message) const {
  if (overridden_.count(key)) return ConfigError("command line", 0, "--set " + key, message);
  return ConfigError(file_, line(key), qualified(key), message);
}

YAML::Node Params::lookup(const std::string& key) {
  asked_.insert(key);
  if (!node_ || !node_.IsMap()) return YAML::Node();
  for (auto it = node_.begin(); it != node_.end(); ++it)
    if (keyText(it->first) == key) return it->second;
  return YAML::Node();
}

bool Params::has(const std::string& key) {
  YAML::Node n = lookup(key);
  return n && !n.IsNull();
}

float Params::toFloat(const YAML::Node& n, const std::string& key) const {
  float v = 0;
  try {
    if (!n.IsScalar()) fail(key, "expected a number, got " + shapeOf(n));
    v = n.as<float>();
  } catch (const YAML::Exception&) {
    // yaml-cpp refuses a number beyond a float (1e39) as not a number: say which.
    double d = 0;
    bool number = false;
    try {
      d = n.as<double>();
      number = true;
    } catch (const YAML::Exception&) {
    }
    if (number && std::isfinite(d)) fail(key, "'" + n.Scalar() + "' is beyond a float's range (about ±3.4e38)");
    fail(key, "expected a number, got '" + n.Scalar() + "'");
  }
  if (!std::isfinite(v)) fail(key, "must be a finite number, got '" + n.Scalar() + "'");
  return v;
}

Vec3 Params::toVec3(const YAML::Node& n, const std::string& key, bool allowScalar) const {
  if (allowScalar && n.IsScalar()) return Vec3(toFloat(n, key));
  if (!n.IsSequence() || n.size() != 3)
    fail(key, std::string(allowScalar ? "expected a number or a list of 3 numbers" : "expected a list of 3 numbers") +
                  ", got " + (n.IsSequence() ? "a list of " + std::to_string(n.size()) : shapeOf(n)));
  return {toFloat(n[0], key), toFloat(n[1], key), toFloat(n[2], key)};
}

std::vector<float> Params::getFloatList(const std::string& key, size_t count) {
  YAML::Node n = lookup(key);
  if (!n || !n.IsSequence() || n.size() != count)
    fail(key, "expected a list of " + std::to_string(count) + " numbers, got " +
                  (n && n.IsSequence() ? "a list of " + std::to_string(n.size()) : shapeOf(n)));
  std::vector<float> v;
  YAML::Node seq(YAML::NodeType::Sequence);
  seq.SetStyle(YAML::EmitterStyle::Flow);
  for (size_t i = 0; i < count; ++i) {
    v.push_back(toFloat(n[i], key));
    seq.push_back(v.back());
  }
  resolved_[key] = seq;
  return v;
}

std::vector<float> Params::getFloatSequence(const std::string& key, size_t multipleOf) {
  if (!has(key)) return {};
  YAML::Node n = lookup(key);
  if (!n.IsSequence() || n.size() == 0 || n.size() % multipleOf != 0)
    fail(key, "expected a list of numbers, " + std::to_string(multipleOf) + " per item, got " +
                  (n.IsSequence() ? "a list of " + std::to_string(n.size()) : shapeOf(n)));
  std::vector<float> v;
  v.reserve(n.size());
  for (size_t i = 0; i < n.size(); ++i) v.push_back(toFloat(n[i], key));
  resolved_[key] = n;
  return v;
}

namespace {
std::string number(double v) {
  char buf[32];
  // Whole numbers in full ("100000000", not "1e+08"), so an integer key's
  // listed range reads back as an integer.
  if (v == std::floor(v) && std::abs(v) < 1e15) std::snprintf(buf, sizeof buf, "%.0f", v);
  else std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}
}  // namespace

std::string Range::text() const {
  if (lo != -HUGE_VAL && hi != HUGE_VAL)
    return (loOpen ? "(" : "[") + number(lo) + ", " + number(hi) + (hiOpen ? ")" : "]");
  if (lo != -HUGE_VAL) return (loOpen ? "> " : ">= ") + number(lo);
  if (hi != HUGE_VAL) return (hiOpen ? "< " : "<= ") + number(hi);
  return "";
}

std::string Range::violation() const {
  if (hi == HUGE_VAL && lo == 0) return loOpen ? "must be positive" : "must not be negative";
  if (hi == HUGE_VAL && !loOpen) return "must be at least " + number(lo);
  return "must be in " + text();
}

void Params::document(const std::string& key, const std::string& type, const std::string& fallback,
                      const std::string& allowed, const std::string& meaning) {
  for (const auto& d : docs_)
    if (d.key == key) return;  // read twice (e.g. max_depth by two readers): the first says it
  docs_.push_back({key, type, fallback, allowed, meaning, condition_});
}

void Params::checkRange(const std::string& key, double v, const KeySpec& spec) const {
  if (!spec.range.contains(v)) fail(key, spec.range.violation());
}

std::vector<KeyDoc> describeKeys(const std::function<void(Params&)>& reader) {
  Params p(YAML::Node(YAML::NodeType::Map), "", "");
  p.describing_ = true;
  reader(p);
  return p.docs_;
}

void Params::failMissing(const std::string& key) const {
  // `texture: {fille: a.exr}` should not say only "'file' is required": the
  // unread key nearest to the required one is named.
  std::vector<std::string> unread;
  if (!describing_ && node_ && node_.IsMap())
    for (auto it = node_.begin(); it != node_.end(); ++it)
      if (it->first.IsScalar() && !asked_.count(it->first.Scalar()) && it->first.Scalar() != key)
        unread.push_back(it->first.Scalar());
  std::string near = closestMatch(key, unread);
  fail(key, near.empty() ? "is required" : "is required (is '" + near + "', given here, a misspelling of it?)");
}

float Params::getFloat(const std::string& key, float fallback, const KeySpec& spec) {
  document(key, "number", number(fallback), spec.allowed.empty() ? spec.range.text() : spec.allowed, spec.meaning);
  YAML::Node n = lookup(key);
  float v = n && !n.IsNull() ? toFloat(n, key) : fallback;
  checkRange(key, v, spec);
  return record(key, v);
}
float Params::requireFloat(const std::string& key) {
  if (!has(key)) failMissing(key);
  return getFloat(key, 0);
}

int Params::getInt(const std::string& key, int fallback, const KeySpec& spec) {
  document(key, "integer", std::to_string(fallback), spec.allowed.empty() ? spec.range.text() : spec.allowed,
           spec.meaning);
  YAML::Node n = lookup(key);
  int v = fallback;
  if (n && !n.IsNull()) {
    try {
      if (!n.IsScalar()) throw YAML::Exception(YAML::Mark(), "");
      v = n.as<int>();
    } catch (const YAML::Exception&) {
      // A whole number too large for an int was called "not an integer".
      long long wide = 0;
      if (n.IsScalar() && YAML::convert<long long>::decode(n, wide))
        fail(key, "must be a whole number in [-2147483648, 2147483647], got " + n.Scalar());
      fail(key, "expected an integer, got " + shapeOf(n));
    }
  }
  checkRange(key, v, spec);
  return record(key, v);
}

bool Params::getBool(const std::string& key, bool fallback, const KeySpec& spec) {
  document(key, "bool", fallback ? "true" : "false", "true, false", spec.meaning);
  YAML::Node n = lookup(key);
  if (!n || n.IsNull()) return record(key, fallback);
  try {
    if (n.IsScalar()) return record(key, n.as<bool>());
  } catch (const YAML::Exception&) {
  }
  fail(key, "expected true or false, got " + shapeOf(n));
}

std::string Params::getString(const std::string& key, const std::string& fallback, const KeySpec& spec) {
  document(key, "string", fallback, "", spec.meaning);
  YAML::Node n = lookup(key);
  if (!n || n.IsNull()) return record(key, fallback);
  if (!n.IsScalar()) fail(key, "expected a string, got " + shapeOf(n));
  return record(key, n.Scalar());
}
std::string Params::requireString(const std::string& key) {
  if (!has(key)) failMissing(key);
  return getString(key, "");
}

std::string Params::getChoice(const std::string& key, const std::string& fallback,
                              const std::vector<std::string>& choices, const KeySpec& spec) {
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
  document(key, "choice", fallback, list, spec.meaning);
  std::string v = getString(key, fallback);
  for (const auto& c : choices)
    if (c == v) return v;
  std::string hint = closestMatch(v, choices);
  fail(key, "unknown value '" + v + "' (expected one of: " + list + ")" +
                (hint.empty() ? "" : "; did you mean '" + hint + "'?"));
}

Vec3 Params::getVec3(const std::string& key, Vec3 fallback) {
  YAML::Node n = lookup(key);
  return recordVec3(key, n && !n.IsNull() ? toVec3(n, key, false) : fallback);
}
Vec3 Params::requireVec3(const std::string& key) {
  if (!has(key)) failMissing(key);
  return getVec3(key, {});
}
Color Params::getColor(const std::string& key, Color fallback) {
  YAML::Node n = lookup(key);
  return recordVec3(key, n && !n.IsNull() ? toVec3(n, key, true) : fallback);
}
Color Params::requireColor(const std::string& key) {
  if (!has(key)) failMissing(key);
  return getColor(key, {});
}

std::optional<Params> Params::getChild(const std::string& key) {
  YAML::Node n = lookup(key);
  if (!n || n.IsNull()) return std::nullopt;
  if (!n.IsMap()) fail(key, "expected a mapping of key: value, got " + shapeOf(n));
  return Params(n, file_, qualified(key));
}

std::vector<Params> Params::getList(const std::string& key) {
  YAML::Node n = lookup(key);
  std::vector<Params> out;
  if (!n || n.IsNull()) return out;
  if (!n.IsSequence()) fail(key, "expected a list, got " + shapeOf(n));
  for (size_t i = 0; i < n.size(); ++i) {
    std::string ctx = qualified(key) + "[" + std::to_string(i) + "]";
    if (!n[i].IsMap()) throw ConfigError(file_, n[i].Mark().line + 1, ctx, "expected a mapping of key: value");
    out.emplace_back(n[i], file_, ctx);
  }
  return out;
}

void Params::checkUnused() const {
  if (!node_ || !node_.IsMap()) return;
  std::vector<std::string> known(asked_.begin(), asked_.end());
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    if (!it->first.IsScalar())
      throw ConfigError(file_, it->first.Mark().line + 1, context_, "a key must be a plain name, got " + shapeOf(it->first));
    std::string key = it->first.Scalar();
    if (asked_.count(key)) continue;
    std::string hint = closestMatch(key, known);
    std::string valid;
    for (const auto& k : known) valid += (valid.empty() ? "" : ", ") + k;
    fail(key, "unknown key" + (hint.empty() ? std::string() : "; did you mean '" + hint + "'?") +
                  (valid.empty() ? " (no keys are read here)" : " (valid keys: " + valid + ")"));
  }
}

std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates) {
  auto distance = [](const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
      size_t diag = row[0];
      row[0] = i;
      for (size_t j = 1; j <= b.size(); ++j) {
        size_t up = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] != b[j - 1])});
        diag = up;
      }
    }
    return row[b.size()];
  };
  std::string best;
  size_t bestDist = std::max<size_t>(2, word.size() / 3) + 1;
  for (const auto& c : candidates) {
    size_t d = distance(word, c);
    if (d < bestDist) bestDist = d, best = c;
  }
  return best;
}

namespace {
// `visited` holds the start offsets of the collections already checked: an
// alias (*a) is the node it names, so it is checked once, not once per use
// ("billion laughs": ten levels of nine aliases, under 1 KB, used to take
// hours here). Two distinct collections never start at the same offset.
void checkMappings(const YAML::Node& node, const std::string& file, const std::string& context,
                   std::set<int>& visited) {
  if (!node.IsSequence() && !node.IsMap()) return;
  if (!visited.insert(node.Mark().pos).second) return;
  if (node.IsSequence()) {
    for (size_t i = 0; i < node.size(); ++i)
      checkMappings(node[i], file, context + "[" + std::to_string(i) + "]", visited);
    return;
  }
  std::map<std::string, int> firstLine;
  for (auto it = node.begin(); it != node.end(); ++it) {
    // A copy (a Node is a handle): yaml-cpp's iterator hands out a proxy
    // that dies at the end of the expression, so a reference to it->first
    // dangles (ASan: stack-use-after-scope, found by fuzz_scene).
    const YAML::Node k = it->first;
    int line = k.Mark().line + 1;
    if (!k.IsScalar())
      throw ConfigError(file, line, context, "a key must be a plain name, got " + shapeOf(k));
    std::string name = context.empty() ? k.Scalar() : context + "." + k.Scalar();
    auto [first, fresh] = firstLine.emplace(k.Scalar(), line);
    if (!fresh) throw ConfigError(file, line, name, "given twice (first at line " + std::to_string(first->second) + ")");
    checkMappings(it->second, file, name, visited);
  }
}
}  // namespace

void checkMappings(const YAML::Node& node, const std::string& file, const std::string& context) {
  std::set<int> visited;
  checkMappings(node, file, context, visited);
}

ConfigError malformedYaml(const std::string& file, const YAML::ParserException& e) {
  // yaml-cpp (0.7) refuses nesting deeper than its DepthGuard's limit with
  // the message "bad file"; say what is wrong.
  if (auto* deep = dynamic_cast<const YAML::DeepRecursion*>(&e))
    return ConfigError(file, e.mark.line + 1, "",
                       "nested more than " + std::to_string(deep->depth() - 1) + " levels deep (the YAML reader's limit)");
  return ConfigError(file, e.mark.line + 1, "", "malformed YAML: " + e.msg);
}

YAML::Node loadYamlFile(const std::string& path) {
  // An ifstream opens a directory and fails only when read, with
  // "basic_filebuf::underflow".
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw ConfigError(path, 0, "", "is a directory, not a YAML file");
  // yaml-cpp builds a node per scalar: a dense flow list costs ~230 bytes of
  // memory and ~1.5 µs per byte of YAML (16 MiB of "[0,0,...]": 25 s, 3.9 GB).
  // A scene or experiment is written by hand and references its meshes, so
  // its YAML is kilobytes; a file this large is a mistake (a mesh pasted in,
  // the wrong file), and is refused before parsing rather than after a minute.
  auto bytes = std::filesystem::file_size(path, ec);
  if (!ec && bytes > kMaxYamlBytes) {
    char msg[200];
    std::snprintf(msg, sizeof msg, "is %.1f MiB; YAML files are read up to %.0f MiB (put meshes in OBJ/PLY files)",
                  double(bytes) / (1 << 20), double(kMaxYamlBytes) / (1 << 20));
    throw ConfigError(path, 0, "", msg);
  }
  // A FIFO or a device would block or never end.
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw ConfigError(path, 0, "", "not a regular file");
  std::ifstream in(path);
  if (!in) throw ConfigError(path, 0, "", "cannot open file");
  YAML::Node root;
  try {
    root = YAML::Load(in);
  } catch (const YAML::ParserException& e) {
    throw malformedYaml(path, e);
  }
  checkMappings(root, path, "");
  return root;
}

}  // namespace lb
