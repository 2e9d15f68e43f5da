// libFuzzer target: the bytes of a texture or environment-map file -> the
// scene loader that reads them (issue 34). The first byte picks the use:
// bit 0 clear, an image texture (bit 1: PNG or EXR; bit 2: srgb) on a
// diffuse material; bit 0 set, an EXR environment map (bit 1: importance or
// uniform sampling). The rest is the file. Its texels then pass the loader's
// checks (negative or non-finite texels, brightest texel × scale, albedo ×
// texture ≤ 1) and, for a map, the importance distribution is built: a crash,
// hang, sanitizer report, or an error that is not a ConfigError naming the
// file's key is a finding.
#include <cstdint>
#include <string>
#include "core/scene_loader.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint8_t mode = data[0];
  const bool envmap = mode & 1, png = !envmap && (mode & 2), srgb = mode & 4;
  std::filesystem::path file = lbfuzz::tempDir() / (png ? "input.png" : "input.exr");
  lbfuzz::writeFile(file, data + 1, size - 1);
  std::string scene =
      "camera: {position: [0, 1, 4], look_at: [0, 1, 0]}\n"
      "film: {width: 4, height: 4}\n"
      "materials:\n"
      "  white: {type: diffuse, albedo: 0.5" +
      (envmap ? std::string("}\n")
              : ", texture: {type: image, file: " + file.filename().string() + ", srgb: " + (srgb ? "true" : "false") +
                    "}}\n") +
      "shapes:\n"
      "  - {type: rectangle, material: white, transform: {rotate_x: -90}}\n" +
      (envmap ? "lights:\n  - {type: environment, file: " + file.filename().string() + ", scale: 2, sampling: " +
                    ((mode & 2) ? "uniform" : "importance") + "}\n"
              : "  - {type: sphere, center: [0, 2, 0], radius: 0.3, emission: 2}\n");
  try {
    lb::SceneFile sf = lb::loadSceneFromString(scene, (lbfuzz::tempDir() / "scene.yaml").string());
  } catch (const std::exception& e) {
    lbfuzz::rejected(e, true);
  }
  std::error_code ec;
  std::filesystem::remove(file, ec);
  return 0;
}
