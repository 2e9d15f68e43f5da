// libFuzzer target: EXR bytes -> readExr, the reader behind given and cached
// references (experiments/reference.cpp calls it directly; there is no other
// EXR reader). A readable image must hold exactly width x height pixels.
#include <cstdint>
#include <cstdio>
#include <exception>
#include "core/image.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::filesystem::path path = lbfuzz::tempDir() / "input.exr";
  lbfuzz::writeFile(path, data, size);
  try {
    lb::Image image = lb::readExr(path.string());
    if (image.width < 0 || image.height < 0 ||
        image.pixels.size() != size_t(image.width) * size_t(image.height)) {
      std::fprintf(stderr, "fuzz: readExr returned %dx%d with %zu pixels\n", image.width, image.height,
                   image.pixels.size());
      std::abort();
    }
    // Touch every pixel so ASan sees a buffer that is shorter than it claims.
    volatile float sum = 0;
    for (const lb::Color& c : image.pixels) sum = sum + c.r + c.g + c.b;
  } catch (const std::exception& e) {
    lbfuzz::rejected(e, false);
  }
  std::error_code ec;
  std::filesystem::remove(path, ec);
  return 0;
}
