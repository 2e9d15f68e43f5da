#pragma once
// Texture and environment-map images in every format the field's scenes use
// (JPEG, PNG of 8 or 16 bits, TGA, BMP, TIFF, Radiance HDR, PFM, EXR), read
// through one library, OpenImageIO. Integer formats hold display-encoded
// values: decoded from sRGB to linear unless raw (Mitsuba's bitmap: 8- and
// 16-bit files are sRGB unless `raw`); float formats are linear already.
// EXR goes through OpenEXR's reader (core/image.h), which checks a header's
// size before allocating; alpha is not read from EXR.
// References and renders stay with OpenEXR (core/image.h).
#include <string>
#include <vector>
#include "core/image.h"

namespace lb {

struct ImageFile {
  Image rgb;                 // linear RGB; a grey file repeats its channel
  std::vector<float> alpha;  // per pixel in [0, 1] if the file has alpha, else empty
  bool integerFormat = false;
};

// The image file extensions read (lower case, with the dot).
const std::vector<std::string>& readableImageExtensions();
bool isReadableImagePath(const std::string& path);
// At most 8192 × 8192 pixels (checked before anything is allocated); throws
// std::runtime_error naming the file and why for anything unreadable.
ImageFile readImageFile(const std::string& path, bool srgbDecode);

}  // namespace lb
