#pragma once
// What an importer of another renderer's scene format returns: the scene as
// lightbench's own description (docs/scene-format.md), which the YAML loader
// then builds, so that every format gets one set of checks and one resolved
// configuration. Importers: core/mitsuba/ (XML) and core/pbrt/ (pbrt-v4).
//
// What an importer does not support is never dropped silently: each kind of
// unsupported element becomes one warning naming the element, its line and
// what was done instead; the loader prints them, or fails on the first under
// --strict.
#include <yaml-cpp/yaml.h>
#include <glm/glm.hpp>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace lb {

struct ImportWarning {
  int line = 0;
  std::string element;  // e.g. <rfilter type="tent">, or Shape "cylinder"
  std::string message;  // what is unsupported and what was done instead
  std::string text(const std::string& file) const;
};

struct ImportedScene {
  YAML::Node scene;  // a lightbench scene description
  // Where each part of `scene` came from, so that an error the YAML loader
  // finds in it ("shapes[3].emission") names the source line: (key prefix, line).
  std::vector<std::pair<std::string, int>> origins;
  std::vector<ImportWarning> warnings;  // one per kind, in file order
  uint64_t sampleCount = 0;             // the file's samples per pixel, 0 if none
  // Integrator parameters that define the integral rather than tune one
  // estimator (the path length): they apply whichever integrator runs.
  std::vector<std::string> sharedIntegratorKeys;
};

// The warnings of one import, one per kind: a kind seen again adds its line
// to the first one's message ("(also lines 12, 30)").
class ImportWarnings {
 public:
  // `kind` groups warnings (e.g. the element's description); `element` is
  // what the warning shows, which may add where it was (an included file).
  void add(const std::string& kind, const std::string& element, int line, const std::string& message);
  // In the order first seen, each with its other lines.
  std::vector<ImportWarning> list() const;

 private:
  std::vector<ImportWarning> warnings_;
  std::vector<std::vector<int>> alsoLines_;
  std::map<std::pair<std::string, std::string>, size_t> index_;
};

// YAML values as both importers write them: a vec3 in flow style, and a 4×4
// matrix row by row (lightbench's `transform: {matrix}`).
YAML::Node flowVec(const glm::dvec3& v);
YAML::Node rowMajor(const glm::dmat4& m);

// True if `path` names a scene format an importer reads (.xml, .pbrt).
bool isImportedScenePath(const std::string& path);
// Dispatches on the extension; throws ConfigError for malformed input.
ImportedScene importScene(const std::string& path);

}  // namespace lb
