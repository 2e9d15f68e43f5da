#include "core/image.h"
#include "core/memory.h"
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <openexr.h>
#include <png.h>
#include <unistd.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
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

void writeExr(const std::string& path, const Image& image) { writeExr(path, image, {}, {}); }

void writeExr(const std::string& path, const Image& image, const std::vector<ExrLayer>& layers,
              const std::map<std::string, std::string>& attributes) {
  std::string tmp = temporaryPathFor(path);
  try {
    Imf::Header header(image.width, image.height);
    for (const auto& [key, value] : attributes) header.insert(key, Imf::StringAttribute(value));
    Imf::FrameBuffer fb;
    auto insert = [&](const std::string& name, const Image& source, int component) {
      if (source.width != image.width || source.height != image.height)
        throw std::runtime_error("layer " + name + " is " + std::to_string(source.width) + "x" +
                                 std::to_string(source.height) + ", the image " + std::to_string(image.width) + "x" +
                                 std::to_string(image.height));
      header.channels().insert(name, Imf::Channel(Imf::FLOAT));
      char* base = reinterpret_cast<char*>(const_cast<Color*>(source.pixels.data()));
      fb.insert(name, Imf::Slice(Imf::FLOAT, base + component * sizeof(float), sizeof(Color), sizeof(Color) * image.width));
    };
    const char* names[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c) insert(names[c], image, c);
    for (const ExrLayer& layer : layers)
      for (size_t c = 0; c < layer.channels.size() && c < 3; ++c) insert(layer.name + "." + layer.channels[c], layer.image, int(c));
    Imf::OutputFile file(tmp.c_str(), header);
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

// Reads an EXR's header alone and refuses one that cannot be a readable image
// before Imf::InputFile sees it: InputFile allocates its line buffers from
// the header as it opens the file (fuzz_exr: 363 bytes declaring 7.5 million
// pixels a line made it allocate 720 MB). OpenEXR's core C API reads only the
// header, and reports errors through a callback instead of printing them.
// Refused: a data window beyond int, or larger than the memory available;
// a file smaller than its declared pixels can be stored in.
constexpr double kMaxExrPixels = 8192.0 * 8192.0;

void checkExrHeader(const std::string& path) {
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  std::string error;
  init.user_data = &error;
  init.error_handler_fn = [](exr_const_context_t ctxt, exr_result_t code, const char* msg) {
    void* user = nullptr;
    if (exr_get_user_data(ctxt, &user) == EXR_ERR_SUCCESS && user && static_cast<std::string*>(user)->empty())
      *static_cast<std::string*>(user) = msg ? msg : exr_get_default_error_message(code);
  };
  exr_context_t ctxt = nullptr;
  exr_result_t rv = exr_start_read(&ctxt, path.c_str(), &init);
  struct Finish {
    exr_context_t* c;
    ~Finish() { exr_finish(c); }
  } finish{&ctxt};
  if (rv != EXR_ERR_SUCCESS) throw std::runtime_error(error.empty() ? exr_get_default_error_message(rv) : error);

  exr_attr_box2i_t dw;
  exr_storage_t storage;
  exr_compression_t compression;
  const exr_attr_chlist_t* channels = nullptr;
  int32_t chunks = 0, linesPerChunk = 1;
  if (exr_get_data_window(ctxt, 0, &dw) != EXR_ERR_SUCCESS || exr_get_storage(ctxt, 0, &storage) != EXR_ERR_SUCCESS ||
      exr_get_compression(ctxt, 0, &compression) != EXR_ERR_SUCCESS ||
      exr_get_channels(ctxt, 0, &channels) != EXR_ERR_SUCCESS || !channels ||
      exr_get_chunk_count(ctxt, 0, &chunks) != EXR_ERR_SUCCESS)
    throw std::runtime_error(error.empty() ? "incomplete header" : error);
  if (storage == EXR_STORAGE_SCANLINE) exr_get_scanlines_per_chunk(ctxt, 0, &linesPerChunk);
  if (dw.max.x < dw.min.x || dw.max.y < dw.min.y) throw std::runtime_error("empty data window");
  int64_t w = int64_t(dw.max.x) - dw.min.x + 1, h = int64_t(dw.max.y) - dw.min.y + 1;

  // Larger than any image lightbench renders or compares with: refused before
  // the header's claim is believed. PIZ, B44, DWA and tiled files have no size
  // bound checkable from the header (below), and fuzz_exr found a 361-byte
  // file claiming 711 million pixels (8.5 GB).
  if (double(w) * double(h) > kMaxExrPixels) {
    char msg[160];
    std::snprintf(msg, sizeof msg, "its data window (%lld x %lld pixels) is larger than the %.0f pixels (8192 x 8192) "
                  "lightbench reads", (long long)w, (long long)h, kMaxExrPixels);
    throw std::runtime_error(msg);
  }
  double bytes = double(w) * double(h) * sizeof(Color);
  if (w > INT32_MAX || h > INT32_MAX || bytes > 0.9 * availableMemoryBytes()) {
    char msg[160];
    std::snprintf(msg, sizeof msg, "its data window (%lld x %lld pixels) would need %.3g GiB, more than the memory available",
                  (long long)w, (long long)h, bytes / (1 << 30));
    throw std::runtime_error(msg);
  }

  // The fewest bytes the file can hold its pixels in (OpenEXR "Technical
  // Introduction", "Scan Lines" and "Data Compression"): every chunk has an
  // 8-byte entry in the offset table, and a scanline chunk an 8-byte header;
  // uncompressed data is stored whole; zlib (ZIP, ZIPS) cannot shrink data
  // more than 1032:1 (zlib's documented limit for deflate) and OpenEXR's RLE
  // stores at most 127 equal bytes in 2. For the other codecs, and for tiled
  // files, only the per-chunk overhead is counted.
  double need = 8.0 * chunks;
  if (storage == EXR_STORAGE_SCANLINE) {
    need += 8.0 * chunks;
    double raw = 0;
    for (int i = 0; i < channels->num_channels; ++i) {
      const exr_attr_chlist_entry_t& c = channels->entries[i];
      double samples = double(w) * double(h) / std::max(1.0, double(c.x_sampling) * double(c.y_sampling));
      raw += samples * (c.pixel_type == EXR_PIXEL_HALF ? 2 : 4);
    }
    if (compression == EXR_COMPRESSION_NONE) need += raw;
    else if (compression == EXR_COMPRESSION_ZIP || compression == EXR_COMPRESSION_ZIPS) need += raw / 1032;
    else if (compression == EXR_COMPRESSION_RLE) need += raw * 2 / 127;
  }
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
}  // namespace

namespace {
// Reads the channels `choose` names for R, G, B (equal names: grey, read once).
Image readExrChannels(const std::string& path,
                      const std::function<std::array<std::string, 3>(const Imf::ChannelList&)>& choose) {
  try {
    checkExrHeader(path);
    Imf::InputFile file(path.c_str());
    std::array<std::string, 3> names = choose(file.header().channels());
    bool grey = names[0] == names[1];
    Imath::Box2i dw = file.header().dataWindow();
    int64_t w = int64_t(dw.max.x) - dw.min.x + 1, h = int64_t(dw.max.y) - dw.min.y + 1;
    // The same bound on the window this reader sees: fuzz_exr found a file
    // whose header the two OpenEXR readers disagree on (checkExrHeader saw a
    // small window, this one 711 million pixels).
    if (w <= 0 || h <= 0 || double(w) * double(h) > kMaxExrPixels) {
      char msg[160];
      std::snprintf(msg, sizeof msg, "its data window (%lld x %lld pixels) is larger than the %.0f pixels (8192 x 8192) "
                    "lightbench reads", (long long)w, (long long)h, kMaxExrPixels);
      throw std::runtime_error(msg);
    }
    Image image{int(w), int(h)};
    Imf::FrameBuffer fb;
    // Slice::Make places the data window's origin (which may be negative)
    // with integer arithmetic: a pointer moved back by it would overflow
    // (fuzz_exr found one).
    char* data = reinterpret_cast<char*>(image.pixels.data());
    // A grey image is read once, into red, and copied to green and blue.
    for (int c = 0; c < (grey ? 1 : 3); ++c)
      fb.insert(names[c], Imf::Slice::Make(Imf::FLOAT, data + c * sizeof(float), dw, sizeof(Color),
                                           sizeof(Color) * size_t(image.width)));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    if (grey)
      for (Color& p : image.pixels) p = Color(p.r);
    return image;
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot read " + path + ": " + e.what());
  }
}
}  // namespace

Image readExr(const std::string& path) { return readExrChannels(path, rgbChannels); }

Image readExrLayer(const std::string& path, const std::string& layer) {
  return readExrChannels(path, [&](const Imf::ChannelList& channels) -> std::array<std::string, 3> {
    auto has = [&](const std::string& c) { return channels.findChannel(layer + "." + c) != nullptr; };
    for (auto triple : {std::array<const char*, 3>{"R", "G", "B"}, std::array<const char*, 3>{"X", "Y", "Z"}})
      if (has(triple[0]) && has(triple[1]) && has(triple[2]))
        return {layer + "." + triple[0], layer + "." + triple[1], layer + "." + triple[2]};
    std::vector<std::string> names;
    for (auto c = channels.begin(); c != channels.end(); ++c) {
      std::string name = c.name();
      if (name.rfind(layer + ".", 0) == 0 && name.find('.', layer.size() + 1) == std::string::npos) names.push_back(name);
    }
    if (names.size() == 1) return {names[0], names[0], names[0]};
    throw std::runtime_error("no layer '" + layer + "' with R, G, B, or X, Y, Z, or one channel");
  });
}

std::map<std::string, std::string> readExrAttributes(const std::string& path) {
  try {
    checkExrHeader(path);
    Imf::InputFile file(path.c_str());
    std::map<std::string, std::string> out;
    for (auto a = file.header().begin(); a != file.header().end(); ++a)
      if (auto* text = dynamic_cast<const Imf::StringAttribute*>(&a.attribute())) out[a.name()] = text->value();
    return out;
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
