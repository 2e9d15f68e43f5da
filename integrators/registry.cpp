#include "integrators/registry.h"
#include "integrators/bdpt/bdpt.h"
#include "integrators/direct/direct_lighting.h"
#include "integrators/direct_optimal/direct_optimal.h"
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
bool isTrue(const YAML::Node& n) {
  try {
    return n && n.IsScalar() && n.as<bool>();
  } catch (const YAML::Exception&) {
    return false;
  }
}
}  // namespace

const std::vector<IntegratorEntry>& integratorRegistry() {
  static const std::vector<IntegratorEntry> table = {
      {"path", "unidirectional path tracing: uniform/cosine/BSDF sampling, NEE, MIS, Russian roulette",
       [](Params& p) { return std::make_unique<PathTracer>(PathTracerSettings::read(p)); },
       [](const YAML::Node& p) {
         return !isTrue(p["regularize"]) && !isTrue(p["mnee"]) && (!p["sms"] || !p["sms"].IsScalar() ||
                                                                  p["sms"].Scalar() == "off");
       }},
      {"light", "light tracing: particles from the lights splatted to the camera (t = 1 strategies)",
       [](Params& p) { return std::make_unique<LightTracer>(LightTracerSettings::read(p)); }, always},
      {"bdpt", "bidirectional path tracing, every (s,t) strategy, MIS balance/power/uniform",
       [](Params& p) { return std::make_unique<Bdpt>(BdptSettings::read(p)); },
       [](const YAML::Node& p) { return !isTrue(p["regularize"]); }},
      {"photon", "photon mapping: caustic + global maps (FLANN kd-tree), NEE, final gathering",
       [](Params& p) { return std::make_unique<PhotonMapper>(PhotonSettings::read(p)); }, never},
      {"sppm", "stochastic progressive photon mapping: per-pixel radius reduction, consistent",
       [](Params& p) { return std::make_unique<Sppm>(SppmSettings::read(p)); }, never},
      {"irradiance_cache", "irradiance caching with gradients (Ward 1988/1992): path or photon-map base estimator",
       [](Params& p) { return std::make_unique<IrradianceCacheIntegrator>(IrradianceCacheSettings::read(p)); }, never},
      {"direct", "direct lighting: emitters seen and reflected once, light and BSDF samples with MIS (the worked example)",
       [](Params& p) { return std::make_unique<DirectLighting>(DirectLightingSettings::read(p)); }, always},
      {"direct_optimal", "direct lighting with optimal MIS (Kondapaneni et al. 2019): per-pixel coefficients solved "
                         "from the pixel's earlier samples, unbiased",
       [](Params& p) { return std::make_unique<DirectOptimal>(DirectOptimalSettings::read(p)); }, always},
      {"vcm", "vertex connection and merging (modes vcm, bpm, ppm, bpt): BDPT's connections and photon merging under one MIS",
       [](Params& p) { return std::make_unique<Vcm>(VcmSettings::read(p)); },
       [](const YAML::Node& p) {
         return p["mode"] && p["mode"].IsScalar() && p["mode"].Scalar() == "bpt" && !isTrue(p["regularize"]);
       }},
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
