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
};

const std::vector<IntegratorEntry>& integratorRegistry();
// `params` holds the integrator's keys (without `name`). Unknown names list the
// valid ones.
std::unique_ptr<Integrator> makeIntegrator(const std::string& name, Params& params, const std::string& file = "",
                                           int line = 0);

}  // namespace lb
