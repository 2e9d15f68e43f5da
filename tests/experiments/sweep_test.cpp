// Parameter sweeps (issue 15): `sweep: {key: [values]}` in a configuration is
// the cartesian product of its values, each member labelled by its values and
// grouped under the configuration's label; bad sweeps name file, line and key.
#include <gtest/gtest.h>
#include <filesystem>
#include <fstream>
#include <set>
#include "experiments/experiment.h"
#include "tests/support/render_helpers.h"

namespace fs = std::filesystem;

namespace lb {
namespace {

class Sweep : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("lightbench-sweep-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    std::ofstream(dir_ / "scene.yaml") << readText(std::string(LIGHTBENCH_SOURCE_DIR) + "/scenes/cornell-box.yaml");
  }
  void TearDown() override { fs::remove_all(dir_); }
  static std::string readText(const std::string& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  Experiment load(const std::string& configuration) {
    std::ofstream(dir_ / "exp.yaml") << "scenes:\n"
                                        "  - scene: scene.yaml\n"
                                        "    resolution: [8, 8]\n"
                                        "    reference: {integrator: path, spp: 4}\n"
                                        "configurations:\n"
                                        "  - {label: PT, integrator: path}\n"
                                        "  - " << configuration << "\n"
                                        "budget: {spp: 1}\n";
    return loadExperiment((dir_ / "exp.yaml").string(), {});
  }
  std::string refused(const std::string& configuration) {
    try {
      load(configuration);
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "accepted";
  }
  fs::path dir_;
};

// A configuration's `sampler:` replaces the scenes' sampler for it, and for
// every member of its sweep.
TEST_F(Sweep, MembersKeepTheConfigurationsSampler) {
  Experiment e = load("{label: PT sobol, integrator: path, sampler: {type: sobol}, sweep: {shadow_rays: [1, 4]}}");
  ASSERT_EQ(e.configurations.size(), 3u);
  EXPECT_FALSE(e.configurations[0].sampler.has_value());
  for (size_t i = 1; i < 3; ++i) {
    ASSERT_TRUE(e.configurations[i].sampler.has_value()) << e.configurations[i].label;
    EXPECT_EQ(e.configurations[i].sampler->type, "sobol");
  }
  EXPECT_NE(refused("{label: S, integrator: path, sampler: {type: owen}}").find("'configurations[1].sampler.type'"),
            std::string::npos);
}

TEST_F(Sweep, ExpandsToTheCartesianProductLabelledByValues) {
  Experiment e = load("{label: SPPM, integrator: sppm, params: {lookup: flann},"
                      " sweep: {relative_radius: [0.005, 0.01, 0.02], alpha: [0.5, 0.7]}}");
  ASSERT_EQ(e.configurations.size(), 1u + 3 * 2);
  EXPECT_TRUE(e.configurations[0].sweepGroup.empty());  // an ordinary configuration is no sweep member
  std::set<std::pair<std::string, std::string>> seen;
  for (size_t i = 1; i < e.configurations.size(); ++i) {
    const Configuration& c = e.configurations[i];
    EXPECT_EQ(c.sweepGroup, "SPPM");
    EXPECT_EQ(c.integrator, "sppm");
    EXPECT_EQ(c.params["lookup"].Scalar(), "flann") << "the configuration's own params are kept";
    std::string r = c.params["relative_radius"].Scalar(), a = c.params["alpha"].Scalar();
    EXPECT_EQ(c.label, "SPPM relative_radius=" + r + ", alpha=" + a);
    EXPECT_EQ(c.sweepValues["alpha"].Scalar(), a);
    seen.insert({r, a});
  }
  EXPECT_EQ(seen.size(), 6u) << "every combination once";
  // File order, the last key fastest: (0.005, 0.5), (0.005, 0.7), (0.01, 0.5), ...
  EXPECT_EQ(e.configurations[1].label, "SPPM relative_radius=0.005, alpha=0.5");
  EXPECT_EQ(e.configurations[2].label, "SPPM relative_radius=0.005, alpha=0.7");
  EXPECT_EQ(e.configurations[6].label, "SPPM relative_radius=0.02, alpha=0.7");
}

TEST_F(Sweep, BadSweepsNameFileLineAndKey) {
  EXPECT_NE(refused("{label: S, integrator: sppm, sweep: {alpha: 0.5}}").find("exp.yaml:7: 'configurations[1].sweep.alpha': expected a non-empty list"),
            std::string::npos);
  EXPECT_NE(refused("{label: S, integrator: sppm, sweep: {alpha: []}}").find("'configurations[1].sweep.alpha'"),
            std::string::npos);
  EXPECT_NE(refused("{label: S, integrator: sppm, params: {alpha: 0.5}, sweep: {alpha: [0.6]}}")
                .find("'configurations[1].sweep.alpha': is also given in params"),
            std::string::npos);
  // A value out of range is found by the integrator's reader, at the sweep's line.
  std::string err = refused("{label: S, integrator: sppm, sweep: {alpha: [0.5, 1.5]}}");
  EXPECT_NE(err.find("exp.yaml:7:"), std::string::npos) << err;
  EXPECT_NE(err.find("alpha': must be in (0, 1)"), std::string::npos) << err;
  err = refused("{label: S, integrator: sppm, sweep: {alpah: [0.5]}}");
  EXPECT_NE(err.find("did you mean 'alpha'"), std::string::npos) << err;
  err = refused("{label: S, integrator: sppm, sweep: {photons_per_pass: [1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17],"
                " alpha: [0.1,0.2,0.3,0.4,0.5,0.6,0.7,0.8,0.9,0.95,0.99,0.999,0.9999,0.3,0.2,0.1]}}");
  EXPECT_NE(err.find("more than 256 combinations"), std::string::npos) << err;
  // Members colliding with another label (file names) are refused.
  err = refused("{label: PT, integrator: path, sweep: {mis: [power]}}\n  - {label: 'PT mis=power', integrator: path}");
  EXPECT_NE(err.find("collides"), std::string::npos) << err;
}

}  // namespace
}  // namespace lb
