// libFuzzer target: a pbrt-v4 scene file -> importPbrtFromString, then the
// YAML loader on its translation (as `lightbench render scene.pbrt` does). A
// ConfigError (or another std::exception) is a clean rejection; a crash,
// abort, hang, sanitizer report or an exception of another type is a finding.
#include <cstdint>
#include <string>
#include "core/pbrt/import.h"
#include "core/scene_loader.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  try {
    lb::ImportedScene imp = lb::importPbrtFromString(text, LIGHTBENCH_SOURCE_DIR "/scenes/fuzz.pbrt");
    lb::SceneFile sf = lb::loadSceneFromString(YAML::Dump(imp.scene), LIGHTBENCH_SOURCE_DIR "/scenes/fuzz.pbrt");
  } catch (const std::exception& e) {
    lbfuzz::rejected(e, true);
  }
  return 0;
}
