#pragma once
// Integrators by name. Adding one is a folder under integrators/ and one line
// in the table in registry.cpp.
#include <functional>
#include <memory>
#include <string>
#include <vector>
#include "core/params.h"
#include "integrators/integrator.h"

namespace lb {

struct IntegratorEntry {
  std::string name;
  std::string summary;
  // Reads the integrator's parameters; must reject unknown keys.
  std::function<std::unique_ptr<Integrator>(Params&)> create;
  // Whether the estimator, with these parameters, is unbiased (its expected
  // value is the image at any sample count): only such an integrator may
  // render an experiment's reference without the user saying otherwise.
  // Consistent ones (photon maps, caches, merging) carry their bias into it.
  std::function<bool(const YAML::Node& params)> unbiased;
};

const std::vector<IntegratorEntry>& integratorRegistry();
// Every key the integrator reads, with type, default, range and meaning: its
// settings reader run on an empty mapping (Params::describing), so the list
// cannot drift from what is read. Throws for an unknown name.
std::vector<KeyDoc> integratorKeys(const std::string& name);
// Whether the integrator reads `key` (one of integratorKeys(name)); true for
// an unknown name, so that makeIntegrator is the one to refuse it. An imported
// scene's max_depth goes to the integrators that read it (withSharedIntegratorKeys).
bool integratorReadsKey(const std::string& name, const std::string& key);
std::function<bool(const std::string& key)> keysReadBy(const std::string& name);
// `params` holds the integrator's keys (without `name`). Unknown names list the
// valid ones.
std::unique_ptr<Integrator> makeIntegrator(const std::string& name, Params& params, const std::string& file = "",
                                           int line = 0);

}  // namespace lb
