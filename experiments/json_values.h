#pragma once
// YAML values as JSON values (meta.json, the Python package's metadata):
// mappings, lists, and scalars as the number or bool they spell (YAML 1.2's
// core schema), else strings; a quoted scalar stays a string.
#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

namespace lb {

nlohmann::json yamlToJson(const YAML::Node& node);

}  // namespace lb
