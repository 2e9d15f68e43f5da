#include "core/scene_import.h"
#include <cctype>
#include <filesystem>
#include "core/mitsuba/import.h"
#include "core/pbrt/import.h"

namespace lb {

std::string ImportWarning::text(const std::string& file) const {
  return file + ":" + std::to_string(line) + ": " + element + ": " + message;
}

bool isImportedScenePath(const std::string& path) { return isMitsubaXmlPath(path) || isPbrtPath(path); }

ImportedScene importScene(const std::string& path) {
  return isPbrtPath(path) ? importPbrt(path) : importMitsubaXml(path);
}

}  // namespace lb
