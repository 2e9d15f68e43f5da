#include "experiments/json_values.h"
#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace lb {

nlohmann::json yamlToJson(const YAML::Node& n) {
  if (!n || n.IsNull()) return nullptr;
  if (n.IsSequence()) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& item : n) a.push_back(yamlToJson(item));
    return a;
  }
  if (n.IsMap()) {
    nlohmann::json o = nlohmann::json::object();
    for (auto it = n.begin(); it != n.end(); ++it) o[it->first.Scalar()] = yamlToJson(it->second);
    return o;
  }
  const std::string& text = n.Scalar();
  if (n.Tag() == "!") return text;  // quoted in the YAML: a string
  if (text == "true" || text == "false") return text == "true";
  // Whole numbers beyond 64 bits (errno) fall through to a double, not a clamped integer.
  char* end = nullptr;
  errno = 0;
  if (!text.empty() && text[0] != '-') {
    unsigned long long u = std::strtoull(text.c_str(), &end, 10);
    if (*end == '\0' && errno == 0) return u;
  } else if (!text.empty()) {
    long long i = std::strtoll(text.c_str(), &end, 10);
    if (*end == '\0' && errno == 0) return i;
  }
  errno = 0;
  double d = std::strtod(text.c_str(), &end);
  if (!text.empty() && *end == '\0' && std::isfinite(d)) return d;
  return text;
}

}  // namespace lb
