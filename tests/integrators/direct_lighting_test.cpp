// The worked example of docs/writing-an-integrator.md: direct lighting must
// estimate what the path tracer estimates with paths of at most two segments
// (max_depth: 2), region by region within the measured noise, with and without
// MIS; and the tutorial shows the integrator's source as it is.
#include <gtest/gtest.h>
#include <fstream>
#include <sstream>
#include "tests/support/render_helpers.h"

namespace lb {
namespace {

using test::compareRegions;
using test::regionMeans;
using test::RenderSpec;

void expectAgreement(const SceneFile& sf, uint64_t spp) {
  auto path = test::renderScene(sf, {"path", "{max_depth: 2}", spp, 1});
  for (const char* params : {"{mis: true}", "{mis: false}"}) {
    auto direct = test::renderScene(sf, {"direct", params, spp, 2});
    EXPECT_EQ(compareRegions(regionMeans(*direct, 4, 4), regionMeans(*path, 4, 4), 1e-3), "") << params;
  }
}

// Diffuse walls, a mirror and a glass sphere (delta lobes: BSDF samples only).
TEST(DirectLighting, AgreesWithTwoSegmentPathTracingInTheCornellBox) {
  expectAgreement(test::loadShippedScene("cornell-box-spheres", 32, 32), 512);
}

// Veach's MIS scene: four glossy plates and four lights of different sizes,
// where light samples and BSDF samples each fail somewhere.
TEST(DirectLighting, AgreesWithTwoSegmentPathTracingOnVeachsMisScene) {
  expectAgreement(test::loadShippedScene("external/veach-mis/scene.xml", 48, 32), 4096);
}

// docs/writing-an-integrator.md lists the two files; this keeps them the same.
TEST(DirectLighting, TheTutorialShowsTheSourceAsItIs) {
  auto read = [](const std::string& path) {
    std::ifstream in(test::sourcePath(path));
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  std::string doc = read("docs/writing-an-integrator.md");
  for (const char* file : {"integrators/direct/direct_lighting.h", "integrators/direct/direct_lighting.cpp"}) {
    std::string source = read(file);
    ASSERT_FALSE(source.empty()) << file;
    EXPECT_NE(doc.find(source), std::string::npos) << file << " differs from its listing in the tutorial";
  }
}

}  // namespace
}  // namespace lb
