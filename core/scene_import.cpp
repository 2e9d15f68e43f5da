#include "core/scene_import.h"
#include <cctype>
#include <filesystem>
#include "core/mitsuba/import.h"
#include "core/pbrt/import.h"

namespace lb {

std::string ImportWarning::text(const std::string& file) const {
  return file + ":" + std::to_string(line) + ": " + element + ": " + message;
}

void ImportWarnings::add(const std::string& kind, const std::string& element, int line, const std::string& message) {
  auto key = std::make_pair(kind, message);
  if (auto it = index_.find(key); it != index_.end()) {
    alsoLines_[it->second].push_back(line);
    return;
  }
  index_[key] = warnings_.size();
  warnings_.push_back({line, element, message});
  alsoLines_.emplace_back();
}

std::vector<ImportWarning> ImportWarnings::list() const {
  std::vector<ImportWarning> out = warnings_;
  for (size_t i = 0; i < out.size(); ++i) {
    const std::vector<int>& also = alsoLines_[i];
    if (also.empty()) continue;
    std::string lines;
    for (size_t k = 0; k < also.size() && k < 5; ++k) lines += (k ? ", " : "") + std::to_string(also[k]);
    if (also.size() > 5) lines += " and " + std::to_string(also.size() - 5) + " more";
    out[i].message += " (also line" + std::string(also.size() > 1 ? "s " : " ") + lines + ")";
  }
  return out;
}

YAML::Node flowVec(const glm::dvec3& v) {
  YAML::Node n(YAML::NodeType::Sequence);
  n.SetStyle(YAML::EmitterStyle::Flow);
  for (int i = 0; i < 3; ++i) n.push_back(v[i]);
  return n;
}

YAML::Node rowMajor(const glm::dmat4& m) {
  YAML::Node n(YAML::NodeType::Sequence);
  n.SetStyle(YAML::EmitterStyle::Flow);
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) n.push_back(m[col][row]);
  return n;
}

bool isImportedScenePath(const std::string& path) { return isMitsubaXmlPath(path) || isPbrtPath(path); }

ImportedScene importScene(const std::string& path) {
  return isPbrtPath(path) ? importPbrt(path) : importMitsubaXml(path);
}

}  // namespace lb
