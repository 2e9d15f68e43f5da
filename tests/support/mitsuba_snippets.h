#pragma once
// Small Mitsuba XML scenes for the importer's tests: a valid scene (one
// camera, an 8 × 8 film) around the elements a test is about.
#include <string>
#include "core/mitsuba/import.h"

namespace lb::test {

// A minimal valid scene around `body` (3.x dialect unless `version` says otherwise);
// `body` starts on line 4.
inline std::string xmlScene(const std::string& body, const std::string& version = "3.0.0") {
  return "<scene version=\"" + version + "\">\n"
         "<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/>\n"
         "<film type=\"hdrfilm\"><integer name=\"width\" value=\"8\"/><integer name=\"height\" value=\"8\"/>"
         "<rfilter type=\"box\"/></film></sensor>\n" +
         body + "</scene>\n";
}

inline MitsubaImport importSnippet(const std::string& xml) { return importMitsubaXmlFromString(xml, "test.xml"); }

}  // namespace lb::test
