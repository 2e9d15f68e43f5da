// `lightbench render scene.xml` as a user runs it: an imported scene renders
// and says what it approximated; a bad one is one line naming file and line,
// exit 2, nothing written; --strict refuses any approximation.
#include "tests/support/bad_input_fixture.h"

namespace lb::testing {
namespace {

const std::string kCornellV06 = std::string(LIGHTBENCH_SOURCE_DIR) + "/scenes/external/cornell-box/scene_v0.6.xml";

TEST_F(BadInput, MitsubaSceneRendersAndListsItsApproximations) {
  RunResult r = render(kCornellV06, "--set max_depth=4", "--spp 1");
  // (--set replaces the file's max_depth 65: a faster test, the same code path.)
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "out" / "image.exr"));
  for (const char* what : {"scene_v0.6.xml:6: <boolean>", "sobol", "ldrfilm", "tent"})
    EXPECT_NE(r.err.find(what), std::string::npos) << "missing '" << what << "' in: " << r.err;
  std::stringstream config;
  config << std::ifstream(dir_ / "out" / "image.config.yaml").rdbuf();
  EXPECT_NE(config.str().find("import_warnings: 4"), std::string::npos) << config.str();
}

TEST_F(BadInput, MitsubaStrictRefusesApproximations) {
  RunResult r = render(kCornellV06, "--strict");
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("scene_v0.6.xml:6:"), std::string::npos) << r.err;
  EXPECT_TRUE(noOutput());
}

TEST_F(BadInput, MitsubaUnknownReferenceIsOneLineWithFileAndLine) {
  std::string f = write("bad.xml",
                        "<scene version=\"3.0.0\">\n"
                        "<sensor type=\"perspective\"><film type=\"hdrfilm\"><rfilter type=\"box\"/></film></sensor>\n"
                        "<integrator type=\"path\"><integer name=\"max_depth\" value=\"4\"/></integrator>\n"
                        "<shape type=\"rectangle\">\n"
                        "  <ref id=\"Flor\"/>\n"
                        "</shape>\n"
                        "</scene>\n");
  RunResult r = render(f);
  expectError(r, "bad.xml:5:", "<ref>.id", "no BSDF with id 'Flor'");
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

}  // namespace
}  // namespace lb::testing
