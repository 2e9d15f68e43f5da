// Every shipped experiment loads: its scenes exist, and every configuration's
// and reference's parameters are valid for its integrator (loadExperiment
// checks them all, without rendering). A typo in a shipped file fails here,
// not half an hour into a run.
#include <gtest/gtest.h>
#include <filesystem>
#include "core/error.h"
#include "experiments/experiment.h"

namespace lb {
namespace {

TEST(ShippedExperiments, EveryFileLoads) {
  int loaded = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(LIGHTBENCH_SOURCE_DIR) + "/experiments")) {
    if (entry.path().extension() != ".yaml") continue;
    try {
      Experiment e = loadExperiment(entry.path().string(), {});
      EXPECT_FALSE(e.configurations.empty()) << entry.path();
      ++loaded;
    } catch (const std::exception& ex) {
      ADD_FAILURE() << entry.path() << ": " << ex.what();
    }
  }
  EXPECT_GE(loaded, 8);
}

}  // namespace
}  // namespace lb
