#include "integrators/registry_docs.h"
#include <algorithm>
#include <iomanip>
#include <sstream>
#include "core/error.h"
#include "integrators/registry.h"

namespace lb {

const std::vector<std::string>& integratorProperties() {
  static const std::vector<std::string> names = {"splits", "unbiased", "adaptive", "replay"};
  return names;
}

namespace {

void checkProperty(const std::string& property, const std::string& flag) {
  const auto& known = integratorProperties();
  if (std::find(known.begin(), known.end(), property) != known.end()) return;
  std::string list;
  for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
  throw ConfigError("command line", 0, flag, "unknown property '" + property + "' (one of: " + list + ")");
}

// Why the integrator, with these parameters, lacks the property ("" when it
// has it): the interface's own refusal where there is one.
std::string whyNot(const IntegratorEntry& e, const std::string& property, const YAML::Node& yaml) {
  if (property == "unbiased") return e.unbiased(yaml) ? "" : "consistent, not unbiased";
  Params p(YAML::Clone(yaml), "", "integrator");
  auto integrator = e.create(p);
  if (property == "splits") return integrator->splitRefusal();
  if (property == "adaptive") return integrator->adaptiveRefusal();
  return integrator->replaysSamples() ? "" : "it does not replay one sample";
}

// The values of `allowed` ("a, b, c") of a choice key.
std::vector<std::string> choices(const std::string& allowed) {
  std::vector<std::string> out;
  std::stringstream s(allowed);
  std::string v;
  while (std::getline(s, v, ',')) out.push_back(v.substr(v.find_first_not_of(' ')));
  return out;
}

// One integrator against a property: at its defaults, and the settings (one
// value of one choice or bool key) under which it differs from its defaults.
struct Setting {
  std::string key, value;
  std::string text() const { return "`" + key + ": " + value + "`"; }
};

struct Exception {
  Setting setting;
  std::string why;  // why it lacks the property there ("" if it has it)
  // Where it lacks the property at its defaults and has it with this
  // setting: the settings of other keys that take it away again (vcm splits
  // in mode bpt, not with regularize: true), each with why.
  std::vector<std::pair<Setting, std::string>> spoilers;
  std::string spoiled() const {
    std::string out;
    for (size_t i = 0; i < spoilers.size(); ++i) out += (i == 0 ? "" : " or ") + spoilers[i].first.text();
    return out.empty() ? out : " (not with " + out + ")";
  }
};

struct Verdict {
  std::string name, why;  // why it lacks the property at its defaults ("" if it has it)
  std::vector<Exception> exceptions;
  std::string joined() const {
    std::string out;
    for (size_t i = 0; i < exceptions.size(); ++i) out += (i == 0 ? "" : " or ") + exceptions[i].setting.text();
    return out;
  }
  // The exceptions with what spoils them: one "(not with …)" after the list
  // when every exception has the same, otherwise after each.
  std::string joinedWithSpoilers() const {
    bool same = true;
    for (const Exception& x : exceptions) same = same && x.spoiled() == exceptions.front().spoiled();
    if (same) return joined() + exceptions.front().spoiled();
    std::string out;
    for (size_t i = 0; i < exceptions.size(); ++i)
      out += (i == 0 ? "" : " or ") + exceptions[i].setting.text() + exceptions[i].spoiled();
    return out;
  }
};

// Every non-default value of each choice and bool key that has no condition
// (a conditional key's values are not settings of their own).
std::vector<Setting> singleSettings(const std::string& integrator) {
  std::vector<Setting> out;
  for (const KeyDoc& k : integratorKeys(integrator)) {
    if ((k.type != "choice" && k.type != "bool") || !k.condition.empty()) continue;
    std::vector<std::string> values = k.type == "bool" ? std::vector<std::string>{"true", "false"} : choices(k.allowed);
    for (const std::string& value : values)
      if (value != k.fallback) out.push_back({k.key, value});
  }
  return out;
}

Verdict judge(const IntegratorEntry& e, const std::string& property) {
  Verdict v{e.name, whyNot(e, property, YAML::Node(YAML::NodeType::Map)), {}};
  const std::vector<Setting> settings = singleSettings(e.name);
  for (const Setting& s : settings) {
    YAML::Node yaml(YAML::NodeType::Map);
    yaml[s.key] = s.value;
    std::string why = whyNot(e, property, yaml);
    if (why.empty() != v.why.empty()) v.exceptions.push_back({s, why, {}});
  }
  if (v.why.empty()) return v;
  for (Exception& x : v.exceptions)
    for (const Setting& other : settings) {
      if (other.key == x.setting.key) continue;
      YAML::Node yaml(YAML::NodeType::Map);
      yaml[x.setting.key] = x.setting.value;
      yaml[other.key] = other.value;
      std::string why;
      try {
        why = whyNot(e, property, yaml);
      } catch (const ConfigError&) {  // a combination the integrator refuses is no setting of it
        continue;
      }
      if (!why.empty()) x.spoilers.push_back({other, why});
    }
  return v;
}

}  // namespace

std::string integratorsWith(const std::string& property) {
  checkProperty(property, "--with");
  std::string out;
  for (const auto& e : integratorRegistry()) {
    Verdict v = judge(e, property);
    std::string item;
    if (v.why.empty()) item = "`" + v.name + "`" + (v.exceptions.empty() ? "" : " (not with " + v.joined() + ")");
    else if (!v.exceptions.empty()) item = "`" + v.name + "` with " + v.joinedWithSpoilers();
    if (!item.empty()) out += (out.empty() ? "" : ", ") + item;
  }
  return out;
}

std::string integratorsWithout(const std::string& property) {
  checkProperty(property, "--without");
  std::string out;
  for (const auto& e : integratorRegistry()) {
    Verdict v = judge(e, property);
    if (!v.why.empty()) {
      out += "- `" + v.name + "`" + (v.exceptions.empty() ? "" : " (not with " + v.joined() + ")") + ": " + v.why + "\n";
      for (const Exception& x : v.exceptions)
        for (const auto& [spoiler, why] : x.spoilers)
          out += "- `" + v.name + "` with " + x.setting.text() + " and " + spoiler.text() + ": " + why + "\n";
    } else {
      for (const Exception& x : v.exceptions) out += "- `" + v.name + "` with " + x.setting.text() + ": " + x.why + "\n";
    }
  }
  return out;
}

std::string integratorNames() {
  std::string out;
  for (const auto& e : integratorRegistry()) out += (out.empty() ? "`" : ", `") + e.name + "`";
  return out;
}

std::string withCurrentIntegratorLists(const std::string& text, const std::string& file) {
  const std::string open = "<!-- integrators ", openEnd = " -->", close = "<!-- /integrators -->";
  std::string out;
  size_t at = 0;
  auto lineOf = [&](size_t pos) { return 1 + int(std::count(text.begin(), text.begin() + long(pos), '\n')); };
  for (size_t start; (start = text.find(open, at)) != std::string::npos;) {
    size_t specEnd = text.find(openEnd, start);
    size_t end = specEnd == std::string::npos ? specEnd : text.find(close, specEnd);
    if (end == std::string::npos)
      throw ConfigError(file, lineOf(start), "integrators", "a generated list without its closing " + close);
    std::string spec = text.substr(start + open.size(), specEnd - start - open.size());
    std::string list;
    if (spec == "--names") list = integratorNames();
    else if (spec.rfind("--with ", 0) == 0) list = integratorsWith(spec.substr(7));
    else if (spec.rfind("--without ", 0) == 0) list = "\n" + integratorsWithout(spec.substr(10));
    else
      throw ConfigError(file, lineOf(start), "integrators",
                        "unknown list '" + spec + "' (--names, --with PROPERTY or --without PROPERTY)");
    out += text.substr(at, specEnd + openEnd.size() - at) + list + close;
    at = end + close.size();
  }
  return out + text.substr(at);
}

std::string formatIntegratorKeys(const std::string& name, bool markdown) {
  const IntegratorEntry* entry = nullptr;
  for (const auto& e : integratorRegistry())
    if (e.name == name) entry = &e;
  std::vector<KeyDoc> keys = integratorKeys(name);
  std::ostringstream out;
  auto allowed = [](const KeyDoc& k) { return k.allowed.empty() ? std::string("any") : k.allowed; };
  auto meaning = [](const KeyDoc& k) { return k.condition.empty() ? k.meaning : k.meaning + " (" + k.condition + " only)"; };
  if (markdown) {
    out << "## " << name << "\n\n" << entry->summary << ".\n\n| key | type | default | allowed | meaning |\n|---|---|---|---|---|\n";
    for (const auto& k : keys)
      out << "| `" << k.key << "` | " << k.type << " | `" << k.fallback << "` | " << allowed(k) << " | " << meaning(k) << " |\n";
    return out.str();
  }
  out << name << ": " << entry->summary << "\n";
  size_t w[4] = {3, 4, 7, 7};
  for (const auto& k : keys) {
    w[0] = std::max(w[0], k.key.size()), w[1] = std::max(w[1], k.type.size());
    w[2] = std::max(w[2], k.fallback.size()), w[3] = std::max(w[3], allowed(k).size());
  }
  auto row = [&](const std::string& a, const std::string& b, const std::string& c, const std::string& d,
                 const std::string& e) {
    out << "  " << std::left << std::setw(int(w[0])) << a << "  " << std::setw(int(w[1])) << b << "  "
        << std::setw(int(w[2])) << c << "  " << std::setw(int(w[3])) << d << "  " << e << "\n";
  };
  row("key", "type", "default", "allowed", "meaning");
  for (const auto& k : keys) row(k.key, k.type, k.fallback, allowed(k), meaning(k));
  return out.str();
}

}  // namespace lb
