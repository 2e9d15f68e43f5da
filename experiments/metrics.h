#pragma once
// Error metrics of an image x against a reference r, over pixels p and RGB
// channels c (N = 3 × pixels). Exactly:
//   RMSE   = sqrt( (1/N) Σ (x − r)² )
//   relMSE = (1/N) Σ (x − r)² / (r² + ε)                 ε = relEpsilon (default 1e-2)
//   MAPE   = (100/N) Σ |x − r| / (|r| + ε)                 in percent, same ε
// Outlier rejection (optional): per-pixel errors (the channel mean of each
// term) above the given percentile are dropped before averaging, separately
// for each metric; 0 keeps every pixel.
#include <array>
#include "core/image.h"

namespace lb {

struct MetricSettings {
  float relEpsilon = 1e-2f;
  float outlierPercentile = 0;  // e.g. 99.9 drops the worst 0.1 % of pixels
};

struct Crop {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // [x0, x1) × [y0, y1); empty = whole image
  bool empty() const { return x1 <= x0 || y1 <= y0; }
};

struct ErrorMetrics {
  double rmse = 0, relMse = 0, mape = 0;
};

ErrorMetrics computeMetrics(const Image& image, const Image& reference, const MetricSettings& settings,
                            const Crop& crop = {});

// Per-pixel relative squared error (channel mean), for the false-colour image.
Image relativeErrorImage(const Image& image, const Image& reference, float relEpsilon);
// log10 of the error mapped through a perceptual colour ramp (dark blue → yellow),
// over [log10 lo, log10 hi].
Image falseColour(const Image& error, float lo, float hi);
Image cropImage(const Image& image, const Crop& crop, int upscale);

}  // namespace lb
