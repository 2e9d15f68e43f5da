#include "integrators/registry.h"
#include <algorithm>
#include <iomanip>
#include <sstream>
#include "integrators/bdpt/bdpt.h"
#include "integrators/direct/direct_lighting.h"
#include "integrators/guided/guided.h"
#include "integrators/irradiance_cache/irradiance_cache_integrator.h"
#include "integrators/light/light_tracer.h"
#include "integrators/mlt/mlt.h"
#include "integrators/path/path_tracer.h"
#include "integrators/photon/photon_integrator.h"
#include "integrators/sppm/sppm.h"
#include "integrators/vcm/vcm.h"

namespace lb {

namespace {
bool always(const YAML::Node&) { return true; }
bool never(const YAML::Node&) { return false; }
}  // namespace

const std::vector<IntegratorEntry>& integratorRegistry() {
  static const std::vector<IntegratorEntry> table = {
      {"path", "unidirectional path tracing: uniform/cosine/BSDF sampling, NEE, MIS, Russian roulette",
       [](Params& p) { return std::make_unique<PathTracer>(PathTracerSettings::read(p)); }, always},
      {"light", "light tracing: particles from the lights splatted to the camera (t = 1 strategies)",
       [](Params& p) { return std::make_unique<LightTracer>(LightTracerSettings::read(p)); }, always},
      {"bdpt", "bidirectional path tracing, every (s,t) strategy, MIS balance/power/uniform",
       [](Params& p) { return std::make_unique<Bdpt>(BdptSettings::read(p)); }, always},
      {"photon", "photon mapping: caustic + global maps (FLANN kd-tree), NEE, final gathering",
       [](Params& p) { return std::make_unique<PhotonMapper>(PhotonSettings::read(p)); }, never},
      {"sppm", "stochastic progressive photon mapping: per-pixel radius reduction, consistent",
       [](Params& p) { return std::make_unique<Sppm>(SppmSettings::read(p)); }, never},
      {"irradiance_cache", "irradiance caching with gradients (Ward 1988/1992): path or photon-map base estimator",
       [](Params& p) { return std::make_unique<IrradianceCacheIntegrator>(IrradianceCacheSettings::read(p)); }, never},
      {"direct", "direct lighting: emitters seen and reflected once, light and BSDF samples with MIS (the worked example)",
       [](Params& p) { return std::make_unique<DirectLighting>(DirectLightingSettings::read(p)); }, always},
      {"vcm", "vertex connection and merging (modes vcm, bpm, ppm, bpt): BDPT's connections and photon merging under one MIS",
       [](Params& p) { return std::make_unique<Vcm>(VcmSettings::read(p)); },
       [](const YAML::Node& p) { return p["mode"] && p["mode"].IsScalar() && p["mode"].Scalar() == "bpt"; }},
      {"guided", "path tracing guided by learned directions: Q-learning (Dahm & Keller 2017) or an SD-tree "
                 "(Müller et al. 2017), mixed with BSDF sampling",
       [](Params& p) { return std::make_unique<GuidedPathTracer>(GuidedSettings::read(p)); }, always},
      {"mlt", "Metropolis light transport in primary sample space: pssmlt (Kelemen 2002, over path or bdpt) or mmlt "
              "(multiplexed over the (s,t) strategies, Hachisuka 2014)",
       [](Params& p) { return std::make_unique<Mlt>(MltSettings::read(p)); }, never},
  };
  return table;
}

std::vector<KeyDoc> integratorKeys(const std::string& name) {
  for (const auto& e : integratorRegistry())
    if (e.name == name) return describeKeys([&](Params& p) { e.create(p); });
  Params none(YAML::Node(YAML::NodeType::Map), "", "");
  makeIntegrator(name, none, "command line", 0);  // throws, listing the names
  return {};
}

bool integratorReadsKey(const std::string& name, const std::string& key) {
  for (const auto& e : integratorRegistry())
    if (e.name == name) {
      for (const KeyDoc& k : integratorKeys(name))
        if (k.key == key) return true;
      return false;
    }
  return true;
}

std::function<bool(const std::string& key)> keysReadBy(const std::string& name) {
  return [name](const std::string& key) { return integratorReadsKey(name, key); };
}

const std::vector<std::string>& integratorProperties() {
  static const std::vector<std::string> names = {"splits", "unbiased", "adaptive", "replay"};
  return names;
}

namespace {

bool hasProperty(const IntegratorEntry& e, const std::string& property, const YAML::Node& yaml) {
  if (property == "unbiased") return e.unbiased(yaml);
  Params p(YAML::Clone(yaml), "", "integrator");
  auto integrator = e.create(p);
  if (property == "splits") return integrator->splitRefusal().empty();
  if (property == "adaptive") return integrator->adaptiveRefusal().empty();
  return integrator->replaysSamples();
}

// The values of `allowed` ("a, b, c") of a choice key.
std::vector<std::string> choices(const std::string& allowed) {
  std::vector<std::string> out;
  std::stringstream s(allowed);
  std::string v;
  while (std::getline(s, v, ',')) out.push_back(v.substr(v.find_first_not_of(' ')));
  return out;
}

}  // namespace

std::string integratorsWith(const std::string& property) {
  const auto& known = integratorProperties();
  if (std::find(known.begin(), known.end(), property) == known.end()) {
    std::string list;
    for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
    throw ConfigError("command line", 0, "--with", "unknown property '" + property + "' (one of: " + list + ")");
  }
  std::string out;
  for (const auto& e : integratorRegistry()) {
    bool byDefault = hasProperty(e, property, YAML::Node(YAML::NodeType::Map));
    std::vector<std::string> exceptions;  // settings under which it differs from its default
    for (const KeyDoc& k : integratorKeys(e.name)) {
      if (k.type != "choice" || !k.condition.empty()) continue;
      for (const std::string& value : choices(k.allowed)) {
        if (value == k.fallback) continue;
        YAML::Node yaml(YAML::NodeType::Map);
        yaml[k.key] = value;
        if (hasProperty(e, property, yaml) != byDefault) exceptions.push_back("`" + k.key + ": " + value + "`");
      }
    }
    std::string joined;
    for (size_t i = 0; i < exceptions.size(); ++i) joined += (i == 0 ? "" : " or ") + exceptions[i];
    std::string item;
    if (byDefault) item = "`" + e.name + "`" + (exceptions.empty() ? "" : " (not with " + joined + ")");
    else if (!exceptions.empty()) item = "`" + e.name + "` with " + joined;
    if (!item.empty()) out += (out.empty() ? "" : ", ") + item;
  }
  return out;
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

std::unique_ptr<Integrator> makeIntegrator(const std::string& name, Params& params, const std::string& file,
                                           int line) {
  std::vector<std::string> names;
  for (const auto& e : integratorRegistry()) {
    if (e.name == name) return e.create(params);
    names.push_back(e.name);
  }
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  std::string hint = closestMatch(name, names);
  throw ConfigError(file, line, "integrator", "unknown integrator '" + name + "' (available: " + list + ")" +
                                                  (hint.empty() ? "" : "; did you mean '" + hint + "'?"));
}

}  // namespace lb
