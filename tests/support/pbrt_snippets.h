#pragma once
// pbrt-v4 snippets for importer tests: a file's text imported as "test.pbrt"
// (beside the sources' scenes/, so relative names resolve there), and the
// imported description loaded into a Scene as `lightbench render` would.
#include <string>
#include <yaml-cpp/yaml.h>
#include "core/pbrt/import.h"
#include "core/scene_loader.h"

namespace lb::test {

inline ImportedScene importPbrtSnippet(const std::string& text) {
  return importPbrtFromString(text, std::string(LIGHTBENCH_SOURCE_DIR) + "/scenes/test.pbrt");
}

inline SceneFile loadPbrtSnippet(const std::string& text) {
  ImportedScene imp = importPbrtSnippet(text);
  return loadSceneFromString(YAML::Dump(imp.scene), std::string(LIGHTBENCH_SOURCE_DIR) + "/scenes/test.pbrt");
}

// The error a snippet raises, or "" if it imports.
inline std::string pbrtErrorOf(const std::string& text) {
  try {
    importPbrtSnippet(text);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace lb::test
