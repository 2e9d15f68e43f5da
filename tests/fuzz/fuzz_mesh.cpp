// libFuzzer target: mesh file bytes -> loadMesh. The first byte chooses the
// extension (OpenMesh picks its reader by it) and whether normals are smoothed;
// the rest is the file. std::runtime_error is loadMesh's documented rejection.
#include <cstdint>
#include <exception>
#include "core/mesh_io.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const bool ply = data[0] & 1;
  const bool smooth = data[0] & 2;
  std::filesystem::path path = lbfuzz::tempDir() / (ply ? "input.ply" : "input.obj");
  lbfuzz::writeFile(path, data + 1, size - 1);
  try {
    lb::MeshLoadResult r = lb::loadMesh(path.string(), lb::Mat4(1.0f), smooth);
  } catch (const std::exception& e) {
    lbfuzz::rejected(e, false);
  }
  std::error_code ec;
  std::filesystem::remove(path, ec);
  return 0;
}
