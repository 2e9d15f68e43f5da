#include "integrators/registry.h"
#include "integrators/path/path_tracer.h"

namespace lb {

const std::vector<IntegratorEntry>& integratorRegistry() {
  static const std::vector<IntegratorEntry> table = {
      {"path", "unidirectional path tracing: uniform/cosine/BSDF sampling, NEE, MIS, Russian roulette",
       [](Params& p) { return std::make_unique<PathTracer>(PathTracerSettings::read(p)); }},
  };
  return table;
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
