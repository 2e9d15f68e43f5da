#pragma once
// Mitsuba scene XML, in the 0.5/0.6 dialect (camelCase, `toWorld`) and the 3.x
// dialect (snake_case, `to_world`), translated into lightbench's own scene
// description (README "Scene files"), which the YAML loader then builds: one
// set of checks, one resolved configuration, whichever format a scene came in.
//
// The XML is parsed by pugixml. What the importer does not support is never
// dropped silently: each unsupported element or property becomes one warning
// naming the element, its line and what was done instead (dropped, or
// approximated as what); the loader prints them, or fails on the first under
// --strict. Errors (malformed XML, an undefined $parameter, an unknown ref,
// a mirrored camera) are ConfigErrors naming file and line.
#include <yaml-cpp/yaml.h>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace lb {

struct ImportWarning {
  int line = 0;
  std::string element;  // e.g. <rfilter type="tent">
  std::string message;  // what is unsupported and what was done instead
  std::string text(const std::string& file) const;
};

struct MitsubaImport {
  YAML::Node scene;  // a lightbench scene description
  // Where each part of `scene` came from, so that an error the YAML loader
  // finds in it ("shapes[3].emission") names the XML line: (key prefix, line).
  std::vector<std::pair<std::string, int>> origins;
  std::vector<ImportWarning> warnings;  // one per kind, in file order
  uint64_t sampleCount = 0;             // the sampler's sample_count, 0 if none
  // Integrator parameters that define the integral rather than tune one
  // estimator (Mitsuba's max_depth): they apply whichever integrator runs.
  std::vector<std::string> sharedIntegratorKeys;
};

// True for a path ending in ".xml" (any case).
bool isMitsubaXmlPath(const std::string& path);
MitsubaImport importMitsubaXml(const std::string& path);
// For tests and the fuzzer: relative file names resolve against virtualPath's folder.
MitsubaImport importMitsubaXmlFromString(const std::string& xml, const std::string& virtualPath);

}  // namespace lb
