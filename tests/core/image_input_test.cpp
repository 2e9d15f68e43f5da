// Texture images through OpenImageIO (core/image_input.h): each format the
// field's scenes use, written here with known values, reads back as the
// format defines them: integer formats decoded from sRGB (the transfer
// function written again below), float formats linear, alpha kept apart.
#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>
#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include "core/image_input.h"

namespace lb {
namespace {

namespace fs = std::filesystem;

double srgbToLinear(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

// A 4 × 2 image: pixel i has channel c = (i * 4 + c + 1) / 40 (all in (0, 1)).
fs::path writeImage(const std::string& name, int channels, OIIO::TypeDesc format) {
  fs::path dir = fs::temp_directory_path() / ("lb-image-input-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  fs::path path = dir / name;
  std::vector<float> pixels(8 * size_t(channels));
  for (size_t i = 0; i < 8; ++i)
    for (int c = 0; c < channels; ++c) pixels[i * channels + c] = float(i * 4 + c + 1) / 40.f;
  if (path.extension() == ".pfm") {
    // OpenImageIO reads PFM but does not write it: the format is a header
    // and little-endian floats, rows from the bottom up (negative scale).
    std::ofstream f(path, std::ios::binary);
    f << "PF\n4 2\n-1.0\n";
    for (int y = 1; y >= 0; --y) f.write(reinterpret_cast<const char*>(&pixels[size_t(y) * 4 * channels]), 4 * channels * sizeof(float));
    return path;
  }
  auto out = OIIO::ImageOutput::create(path.string());
  EXPECT_TRUE(out) << name;
  OIIO::ImageSpec spec(4, 2, channels, format);
  if (channels == 4) spec.alpha_channel = 3;
  EXPECT_TRUE(out->open(path.string(), spec)) << out->geterror();
  EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data())) << out->geterror();
  out->close();
  return path;
}

double written(size_t pixel, int channel) { return double(pixel * 4 + channel + 1) / 40.0; }

TEST(ImageInput, IntegerFormatsAreDecodedFromSrgbAndFloatOnesAreLinear) {
  struct Case {
    const char* name;
    OIIO::TypeDesc format;
    bool integer;
    double tolerance;  // the format's quantisation (in the stored value)
  };
  const Case cases[] = {{"a.png", OIIO::TypeDesc::UINT8, true, 0.5 / 255},
                        {"a16.png", OIIO::TypeDesc::UINT16, true, 0.5 / 65535},
                        {"a.tga", OIIO::TypeDesc::UINT8, true, 0.5 / 255},
                        {"a.bmp", OIIO::TypeDesc::UINT8, true, 0.5 / 255},
                        {"a.exr", OIIO::TypeDesc::HALF, false, 1e-3},
                        {"a.pfm", OIIO::TypeDesc::FLOAT, false, 1e-7},
                        {"a.hdr", OIIO::TypeDesc::FLOAT, false, 0.01}};  // RGBE: 8-bit mantissas
  for (const Case& c : cases) {
    fs::path p = writeImage(c.name, 3, c.format);
    for (bool srgb : {true, false}) {
      ImageFile f = readImageFile(p.string(), srgb);
      EXPECT_EQ(f.integerFormat, c.integer) << c.name;
      ASSERT_EQ(f.rgb.width, 4);
      ASSERT_EQ(f.rgb.height, 2);
      EXPECT_TRUE(f.alpha.empty());
      for (size_t i = 0; i < 8; ++i)
        for (int ch = 0; ch < 3; ++ch) {
          double v = written(i, ch), expected = c.integer && srgb ? srgbToLinear(v) : v;
          // The quantisation step in the stored value, carried through the decoding's slope.
          double slope = c.integer && srgb ? (srgbToLinear(v + 1e-4) - srgbToLinear(v - 1e-4)) / 2e-4 : 1;
          EXPECT_NEAR(f.rgb.at(int(i % 4), int(i / 4))[ch], expected, c.tolerance * slope * 1.01 + (c.integer ? 0 : c.tolerance * v))
              << c.name << " pixel " << i << " channel " << ch << " srgb " << srgb;
        }
    }
  }
}

TEST(ImageInput, JpegIsReadWithinItsCompressionError) {
  fs::path p = writeImage("a.jpg", 3, OIIO::TypeDesc::UINT8);
  ImageFile f = readImageFile(p.string(), false);
  EXPECT_TRUE(f.integerFormat);
  double worst = 0;
  for (size_t i = 0; i < 8; ++i)
    for (int ch = 0; ch < 3; ++ch) worst = std::max(worst, std::abs(double(f.rgb.at(int(i % 4), int(i / 4))[ch]) - written(i, ch)));
  EXPECT_LT(worst, 0.05);  // lossy; default quality
}

TEST(ImageInput, AlphaIsKeptApartAndGreyRepeats) {
  ImageFile rgba = readImageFile(writeImage("rgba.png", 4, OIIO::TypeDesc::UINT8).string(), true);
  ASSERT_EQ(rgba.alpha.size(), 8u);
  for (size_t i = 0; i < 8; ++i) {
    EXPECT_NEAR(rgba.alpha[i], written(i, 3), 0.5 / 255 + 1e-6);
    // Colour not premultiplied by alpha: the stored value, decoded.
    EXPECT_NEAR(rgba.rgb.at(int(i % 4), int(i / 4)).r, srgbToLinear(written(i, 0)), 0.01);
  }
  ImageFile grey = readImageFile(writeImage("grey.png", 1, OIIO::TypeDesc::UINT8).string(), false);
  EXPECT_TRUE(grey.alpha.empty());
  for (size_t i = 0; i < 8; ++i) {
    Color c = grey.rgb.at(int(i % 4), int(i / 4));
    EXPECT_NEAR(c.r, written(i, 0), 0.5 / 255 + 1e-6);
    EXPECT_EQ(c.r, c.g);
    EXPECT_EQ(c.r, c.b);
  }
}

TEST(ImageInput, AnUnreadableFileNamesItself) {
  fs::path dir = fs::temp_directory_path() / ("lb-image-input-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "junk.png") << "not a png";
  try {
    readImageFile((dir / "junk.png").string(), true);
    FAIL() << "junk read as an image";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("junk.png"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace lb
