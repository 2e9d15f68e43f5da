#include "core/image.h"
#include "core/memory.h"
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <png.h>
#include <unistd.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <stdexcept>

namespace lb {

std::string temporaryPathFor(const std::string& path) {
  std::filesystem::path p(path);
  return (p.parent_path() / ("." + p.filename().string() + ".tmp-" + std::to_string(getpid()))).string();
}

namespace {
void commit(const std::string& tmp, const std::string& path) {
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp);
    throw std::runtime_error("cannot write " + path + ": " + ec.message());
  }
}
}  // namespace

void writeExr(const std::string& path, const Image& image) {
  std::string tmp = temporaryPathFor(path);
  try {
    Imf::Header header(image.width, image.height);
    const char* names[3] = {"R", "G", "B"};
    for (const char* n : names) header.channels().insert(n, Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(tmp.c_str(), header);
    Imf::FrameBuffer fb;
    char* base = reinterpret_cast<char*>(const_cast<Color*>(image.pixels.data()));
    for (int c = 0; c < 3; ++c)
      fb.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), sizeof(Color), sizeof(Color) * image.width));
    file.setFrameBuffer(fb);
    file.writePixels(image.height);
  } catch (const std::exception& e) {
    std::filesystem::remove(tmp);
    throw std::runtime_error("cannot write " + path + ": " + e.what());
  }
  commit(tmp, path);
}

namespace {
// The channels that hold red, green and blue: R, G, B; else those of the one
// layer that has all three (e.g. color.R, color.G, color.B); else Y (grey)
// three times. Anything else is refused with the channels found, never read
// as black (a missing channel would silently fill with zeros).
std::array<std::string, 3> rgbChannels(const Imf::ChannelList& channels) {
  auto has = [&](const std::string& name) { return channels.findChannel(name) != nullptr; };
  if (has("R") && has("G") && has("B")) return {"R", "G", "B"};
  std::set<std::string> layers, rgbLayers;
  channels.layers(layers);
  for (const auto& l : layers)
    if (has(l + ".R") && has(l + ".G") && has(l + ".B")) rgbLayers.insert(l);
  if (rgbLayers.size() == 1) {
    const std::string& l = *rgbLayers.begin();
    return {l + ".R", l + ".G", l + ".B"};
  }
  // Y with chroma (RY, BY) is a colour image that Y alone would turn grey.
  if (rgbLayers.empty() && has("Y") && !has("RY") && !has("BY")) return {"Y", "Y", "Y"};
  std::string found;
  for (auto c = channels.begin(); c != channels.end(); ++c) found += (found.empty() ? "" : ", ") + std::string(c.name());
  if (rgbLayers.size() > 1) {
    std::string list;
    for (const auto& l : rgbLayers) list += (list.empty() ? "" : ", ") + l;
    throw std::runtime_error("several layers have R, G, B (" + list + "); found channels: " + found);
  }
  throw std::runtime_error("no R, G, B (or Y) channels; found: " + (found.empty() ? std::string("none") : found));
}

// The fewest bytes a scanline EXR can hold its data window in, from the file
// layout (OpenEXR "Technical Introduction", "Scan Lines" and "Data
// Compression"): every chunk of scan lines has an 8-byte entry in the offset
// table and an 8-byte chunk header; uncompressed data is stored whole; zlib
// (ZIP, ZIPS) cannot shrink data more than 1032:1 (zlib's documented limit for
// deflate) and OpenEXR's RLE stores at most 127 equal bytes in 2. For the
// other codecs only the per-chunk overhead is counted. A header declaring more
// pixels than its file can hold is corrupt; reading it would allocate the
// image first (found by fuzz_exr: 361 bytes declaring 7.5 million ZIP pixels).
double minimumScanlineFileBytes(const Imf::Header& header, int64_t w, int64_t h) {
  int linesPerChunk = 1;
  switch (header.compression()) {
    case Imf::ZIP_COMPRESSION: case Imf::PXR24_COMPRESSION: linesPerChunk = 16; break;
    case Imf::PIZ_COMPRESSION: case Imf::B44_COMPRESSION: case Imf::B44A_COMPRESSION:
    case Imf::DWAA_COMPRESSION: linesPerChunk = 32; break;
    case Imf::DWAB_COMPRESSION: linesPerChunk = 256; break;
    default: break;
  }
  double chunks = std::ceil(double(h) / linesPerChunk);
  double rawBytes = 0;
  for (auto c = header.channels().begin(); c != header.channels().end(); ++c) {
    const Imf::Channel& ch = c.channel();
    double samples = double(w) * double(h) / std::max(1, ch.xSampling * ch.ySampling);
    rawBytes += samples * (ch.type == Imf::HALF ? 2 : 4);
  }
  double data = 0;
  switch (header.compression()) {
    case Imf::NO_COMPRESSION: data = rawBytes; break;
    case Imf::ZIP_COMPRESSION: case Imf::ZIPS_COMPRESSION: data = rawBytes / 1032; break;
    case Imf::RLE_COMPRESSION: data = rawBytes * 2 / 127; break;
    default: break;
  }
  return 16 * chunks + data;
}
}  // namespace

Image readExr(const std::string& path) {
  try {
    Imf::InputFile file(path.c_str());
    std::array<std::string, 3> names = rgbChannels(file.header().channels());
    bool grey = names[0] == names[1];
    Imath::Box2i dw = file.header().dataWindow();
    if (dw.max.x < dw.min.x || dw.max.y < dw.min.y) throw std::runtime_error("empty data window");
    // The header's data window sizes the image before any pixel is read: a
    // corrupt or hostile header must not make us allocate what we cannot
    // hold (found by fuzz_exr: a 1.9 KB file claiming 1000000 × 200 pixels).
    int64_t w = int64_t(dw.max.x) - dw.min.x + 1, h = int64_t(dw.max.y) - dw.min.y + 1;
    double bytes = double(w) * double(h) * sizeof(Color);
    if (w > INT32_MAX || h > INT32_MAX || bytes > 0.9 * availableMemoryBytes()) {
      char msg[160];
      std::snprintf(msg, sizeof msg, "its data window (%lld x %lld pixels) would need %.3g GiB, more than the memory available",
                    (long long)w, (long long)h, bytes / (1 << 30));
      throw std::runtime_error(msg);
    }
    if (!file.header().hasTileDescription()) {
      double need = minimumScanlineFileBytes(file.header(), w, h);
      std::error_code ec;
      auto have = std::filesystem::file_size(path, ec);
      if (!ec && double(have) < need) {
        char msg[200];
        std::snprintf(msg, sizeof msg, "its header declares %lld x %lld pixels, which need at least %.0f bytes, "
                      "but the file has %llu: truncated or corrupt", (long long)w, (long long)h, need,
                      (unsigned long long)have);
        throw std::runtime_error(msg);
      }
    }
    Image image{int(w), int(h)};
    Imf::FrameBuffer fb;
    char* base = reinterpret_cast<char*>(image.pixels.data()) -
                 (size_t(dw.min.x) + size_t(dw.min.y) * image.width) * sizeof(Color);
    // A grey image is read once, into red, and copied to green and blue.
    for (int c = 0; c < (grey ? 1 : 3); ++c)
      fb.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), sizeof(Color), sizeof(Color) * image.width));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    if (grey)
      for (Color& p : image.pixels) p = Color(p.r);
    return image;
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot read " + path + ": " + e.what());
  }
}

void writePng(const std::string& path, const Image& image, float exposure) {
  std::string tmp = temporaryPathFor(path);
  FILE* fp = std::fopen(tmp.c_str(), "wb");
  if (!fp) throw std::runtime_error("cannot write " + path);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(fp);
    std::filesystem::remove(tmp);
    throw std::runtime_error("cannot write " + path);
  }
  png_init_io(png, fp);
  png_set_IHDR(png, info, image.width, image.height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  float scale = std::exp2(exposure);
  std::vector<unsigned char> row(size_t(image.width) * 3);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c) {
        float v = glm::clamp(image.at(x, y)[c] * scale, 0.f, 1.f);
        v = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1 / 2.4f) - 0.055f;
        row[size_t(x) * 3 + c] = static_cast<unsigned char>(std::lround(v * 255));
      }
    png_write_row(png, row.data());
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(fp);
  commit(tmp, path);
}

void writeTextFile(const std::string& path, const std::string& content) {
  std::string tmp = temporaryPathFor(path);
  {
    std::ofstream out(tmp);
    out << content;
    if (!out) {
      std::filesystem::remove(tmp);
      throw std::runtime_error("cannot write " + path);
    }
  }
  commit(tmp, path);
}

}  // namespace lb
