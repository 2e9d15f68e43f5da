#pragma once
// A float RGB image and its files: OpenEXR (32-bit float channels, exact round
// trip) and an sRGB PNG preview. Files are written under a temporary name in
// the same folder and renamed, so a reader never sees a partial file.
#include <map>
#include <string>
#include <vector>
#include "core/math.h"

namespace lb {

struct Image {
  int width = 0, height = 0;
  std::vector<Color> pixels;
  Image() = default;
  Image(int w, int h) : width(w), height(h), pixels(size_t(w) * size_t(h), Color(0.f)) {}
  Color& at(int x, int y) { return pixels[size_t(y) * width + x]; }
  const Color& at(int x, int y) const { return pixels[size_t(y) * width + x]; }
};

void writeExr(const std::string& path, const Image& image);
// A named layer of a multi-layer EXR: channels "<name>.<c>" for each of
// `channels` (1 to 3 names, e.g. {"R", "G", "B"}, {"X", "Y", "Z"}, {"Z"}),
// taken from the Color's r, g, b in that order.
struct ExrLayer {
  std::string name;
  std::vector<std::string> channels;
  Image image;
};
// The main image as R, G, B (what readExr and every viewer show), the layers
// beside it, and `attributes` as string attributes of the header (lightbench
// writes its integrator, parameters, spp, time, seed and commit there).
void writeExr(const std::string& path, const Image& image, const std::vector<ExrLayer>& layers,
              const std::map<std::string, std::string>& attributes);
// One layer read back: its R, G, B or X, Y, Z channels, or its one channel into r, g and b.
Image readExrLayer(const std::string& path, const std::string& layer);
// The header's string attributes.
std::map<std::string, std::string> readExrAttributes(const std::string& path);
// R, G, B; or the one layer with R, G, B (color.R, …); or Y as grey. Other
// channel sets are an error listing the channels found. At most 8192 x 8192
// pixels (a header claiming more is refused before anything is allocated).
Image readExr(const std::string& path);
// Tone mapping: multiply by 2^exposure, clamp, sRGB transfer curve.
void writePng(const std::string& path, const Image& image, float exposure = 0);
// Writes `content` to `path` through a temporary file and a rename.
void writeTextFile(const std::string& path, const std::string& content);
// A temporary name beside `path`, unique to this process.
std::string temporaryPathFor(const std::string& path);

}  // namespace lb
