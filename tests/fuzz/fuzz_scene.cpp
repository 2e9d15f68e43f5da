// libFuzzer target: scene YAML text -> loadSceneFromString. A ConfigError (or
// another std::exception) is a clean rejection; a crash, abort, hang,
// sanitizer report or an exception of another type is a finding.
#include <cstdint>
#include <string>
#include "core/scene_loader.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  try {
    // Mesh paths resolve against scenes/ so that seeds naming meshes/ring.obj
    // exercise the mesh path too; the fuzzer only ever reads files there.
    lb::SceneFile sf = lb::loadSceneFromString(text, LIGHTBENCH_SOURCE_DIR "/scenes/fuzz.yaml");
  } catch (const std::exception& e) {
    lbfuzz::rejected(e, true);
  }
  return 0;
}
