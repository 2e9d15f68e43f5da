#include "core/image_input.h"
#include <OpenImageIO/imageio.h>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <stdexcept>

namespace lb {

const std::vector<std::string>& readableImageExtensions() {
  static const std::vector<std::string> ext = {".png", ".jpg", ".jpeg", ".tga", ".bmp", ".tif", ".tiff",
                                               ".hdr", ".pfm", ".exr"};
  return ext;
}

bool isReadableImagePath(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  const auto& all = readableImageExtensions();
  return std::find(all.begin(), all.end(), e) != all.end();
}

ImageFile readImageFile(const std::string& path, bool srgbDecode) {
  namespace OIIO = OIIO_NAMESPACE;
  auto fail = [&](const std::string& why) { throw std::runtime_error("cannot read " + path + ": " + why); };
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".exr") {
    // OpenEXR's own reader, the one references use: it refuses an oversized
    // header before allocating (OpenImageIO's open() allocates for the data
    // window first, minutes under the fuzzers' sanitizers).
    ImageFile out;
    out.rgb = readExr(path);
    return out;
  }
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    std::string why = OIIO::geterror();
    fail(why.empty() ? "not an image OpenImageIO reads" : why);
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) fail("an empty image");
  if (double(spec.width) * double(spec.height) > 8192.0 * 8192.0)
    fail("larger than the 8192 x 8192 pixels lightbench reads");
  if (spec.depth > 1) fail("a volume image");
  const int channels = std::min(spec.nchannels, 4);
  std::vector<float> data(size_t(spec.width) * size_t(spec.height) * size_t(channels));
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, data.data())) {
    std::string why = in->geterror();
    fail(why.empty() ? "the pixels could not be decoded" : why);
  }
  in->close();
  ImageFile out;
  out.integerFormat = !spec.format.is_floating_point();
  // Grey, grey + alpha, RGB, RGBA (a fourth channel is alpha when the file says so).
  const bool alpha = channels == 2 || (channels == 4 && spec.alpha_channel == 3) ||
                     (channels == 4 && spec.alpha_channel < 0);
  const bool grey = channels <= 2;
  auto decode = [&](float v) {
    if (!out.integerFormat || !srgbDecode) return v;
    // The sRGB transfer function (IEC 61966-2-1), inverted.
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
  };
  out.rgb = Image(spec.width, spec.height);
  if (alpha) out.alpha.resize(out.rgb.pixels.size());
  for (size_t i = 0; i < out.rgb.pixels.size(); ++i) {
    const float* px = &data[i * size_t(channels)];
    out.rgb.pixels[i] = grey ? Color(decode(px[0])) : Color(decode(px[0]), decode(px[1]), decode(px[2]));
    if (alpha) out.alpha[i] = std::clamp(px[channels - 1], 0.f, 1.f);
  }
  return out;
}

}  // namespace lb
