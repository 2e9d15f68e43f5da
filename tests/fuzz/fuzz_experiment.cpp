// libFuzzer target: experiment YAML bytes -> loadExperiment (parse and
// validate only; nothing renders). The file is written to
// <temp>/experiments/fuzz.yaml beside a <temp>/scenes link to the real scenes,
// so the `../scenes/...` paths of the seeds resolve as they do in the repo.
#include <cstdint>
#include <exception>
#include "experiments/experiment.h"
#include "tests/fuzz/fuzz_common.h"

namespace {
std::filesystem::path experimentPath() {
  const std::filesystem::path& dir = lbfuzz::tempDir();
  std::filesystem::create_directories(dir / "experiments");
  std::error_code ec;
  std::filesystem::create_directory_symlink(LIGHTBENCH_SOURCE_DIR "/scenes", dir / "scenes", ec);
  return dir / "experiments" / "fuzz.yaml";
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::filesystem::path path = experimentPath();
  lbfuzz::writeFile(path, data, size);
  try {
    // Alternate --quick on and off (it changes budgets and reference budgets).
    lb::ExperimentOptions options;
    options.quick = size % 2 == 1;
    lb::Experiment e = lb::loadExperiment(path.string(), options);
  } catch (const std::exception& e) {
    lbfuzz::rejected(e, true);
  }
  return 0;
}
