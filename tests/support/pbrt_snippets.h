#pragma once
// pbrt-v4 snippets for importer tests: a file's text imported as "test.pbrt"
// (beside the sources' scenes/, so relative names resolve there), and the
// imported description loaded into a Scene as `lightbench render` would.
#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <string>
#include <yaml-cpp/yaml.h>
#include "core/pbrt/import.h"
#include "core/scene_loader.h"

namespace lb::test {

inline ImportedScene importPbrtSnippet(const std::string& text) {
  return importPbrtFromString(text, std::string(LIGHTBENCH_SOURCE_DIR) + "/scenes/test.pbrt");
}

// Through a file in a scratch folder, as `lightbench render` loads it; its
// warnings are kept in SceneFile::warnings, not printed.
inline SceneFile loadPbrtSnippet(const std::string& text) {
  namespace fs = std::filesystem;
  fs::path dir = fs::temp_directory_path() / ("lb-pbrt-snippet-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "test.pbrt") << text;
  SceneLoadOptions options;
  options.deferWarnings = true;
  SceneFile sf = loadScene((dir / "test.pbrt").string(), YAML::Node(), options);
  fs::remove_all(dir);
  return sf;
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
