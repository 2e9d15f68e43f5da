// Writes a few tiny EXRs with lb::writeExr into the folder given: the seed
// corpus of fuzz_exr (scripts/fuzz.sh), so the fuzzer starts from files the
// project itself produces rather than from nothing.
#include <cmath>
#include <cstdio>
#include <string>
#include "core/image.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUTPUT_DIR\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  const int sizes[][2] = {{1, 1}, {2, 3}, {4, 4}, {16, 1}};
  for (const auto& s : sizes) {
    lb::Image image(s[0], s[1]);
    for (int y = 0; y < s[1]; ++y)
      for (int x = 0; x < s[0]; ++x) image.at(x, y) = lb::Color(float(x), float(y), 0.5f);
    lb::writeExr(dir + "/seed-" + std::to_string(s[0]) + "x" + std::to_string(s[1]) + ".exr", image);
  }
  lb::Image special(3, 1);  // values a renderer can produce: NaN, infinity, zero
  special.at(0, 0) = lb::Color(NAN);
  special.at(1, 0) = lb::Color(INFINITY);
  lb::writeExr(dir + "/seed-special.exr", special);
  return 0;
}
