// `lightbench render scene.pbrt` as a user runs it: Bitterli's pbrt-v4 export
// renders and says what it approximated; a malformed file is one line naming
// file:line:column, exit 2, nothing written; --strict refuses approximations.
#include <yaml-cpp/yaml.h>
#include "tests/support/bad_input_fixture.h"

namespace lb::testing {
namespace {

const std::string kCornellPbrt = std::string(LIGHTBENCH_SOURCE_DIR) + "/scenes/external/cornell-box/pbrt/scene-v4.pbrt";

TEST_F(BadInput, PbrtSceneRendersWithItsSettings) {
  RunResult r = render(kCornellPbrt, "--set max_depth=4 --resolution 16x16", "--spp 1");
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "out" / "image.exr"));
  YAML::Node config = YAML::LoadFile((dir_ / "out" / "image.config.yaml").string());
  std::stringstream text;
  text << config;
  // Its triangle filter of radius 1, read as lightbench's tent.
  EXPECT_NE(text.str().find("type: tent"), std::string::npos) << text.str();
}

TEST_F(BadInput, PbrtMalformedFileIsOneLineWithLineAndColumn) {
  std::string f = write("bad.pbrt",
                        "Camera \"perspective\"\n"
                        "WorldBegin\n"
                        "Shape \"sphere\" \"float radius\" [ 1 2x ]\n");
  RunResult r = render(f);
  expectError(r, "bad.pbrt:3:35:", "", "expected a finite number in \"float radius\", got '2x'");
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST_F(BadInput, PbrtErrorFoundByTheLoaderNamesTheDirectivesLine) {
  std::string f = write("bad.pbrt",
                        "Camera \"perspective\"\n"
                        "WorldBegin\n"
                        "AttributeBegin\n"
                        "AreaLightSource \"diffuse\" \"rgb L\" [ -1 1 1 ]\n"
                        "Shape \"sphere\"\n"
                        "AttributeEnd\n");
  RunResult r = render(f);
  expectError(r, "bad.pbrt:5:", "emission", "negative");
}

TEST_F(BadInput, PbrtStrictRefusesApproximations) {
  std::string f = write("cyl.pbrt", "WorldBegin\nShape \"sphere\"\nShape \"cylinder\"\n");
  RunResult ok = render(f, "--resolution 8x8");
  EXPECT_EQ(ok.exitCode, 0) << ok.err;
  EXPECT_NE(ok.err.find("cyl.pbrt:3: Shape \"cylinder\": shape 'cylinder' not supported; dropped"), std::string::npos) << ok.err;
  fs::remove_all(dir_ / "out");
  RunResult strict = render(f, "--strict --resolution 8x8");
  EXPECT_EQ(strict.exitCode, 2) << strict.err;
  EXPECT_EQ(std::count(strict.err.begin(), strict.err.end(), '\n'), 1) << strict.err;
  EXPECT_NE(strict.err.find("cyl.pbrt:3:"), std::string::npos) << strict.err;
  EXPECT_TRUE(noOutput());
}

}  // namespace
}  // namespace lb::testing
