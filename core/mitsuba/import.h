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
#include <string>
#include "core/scene_import.h"

namespace lb {

using MitsubaImport = ImportedScene;

// True for a path ending in ".xml" (any case).
bool isMitsubaXmlPath(const std::string& path);
MitsubaImport importMitsubaXml(const std::string& path);
// For tests and the fuzzer: relative file names resolve against virtualPath's folder.
MitsubaImport importMitsubaXmlFromString(const std::string& xml, const std::string& virtualPath);

}  // namespace lb
