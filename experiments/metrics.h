#pragma once
// Error metrics of an image x against a reference r, over pixels p and RGB
// channels c. Each squared-error metric is a mean over the pixels of a
// region P (the whole image or the crop) of
//     e_p = (1/3) Σ_c w_pc (x_pc − r_pc)²,
// with w = 1 for MSE (RMSE = sqrt MSE) and w = 1/(r² + ε) for relMSE
// (ε = relEpsilon, default 1e-2). relMSE trimmed drops the fraction
// trimFraction (default 0.001, SeeSharp's 0.1 %) of the pixels with the
// largest e_p before averaging (at least one pixel is kept).
//   MAPE = (100/N) Σ |x − r| / (|r| + ε), in percent, over all N values.
//
// Corrected for the reference's noise (issue 32): a reference that is a
// mean of independent chunks has a per-pixel variance of the mean v_pc,
// and for x independent of r, E[(x − r)²] = E[(x − μ)²] + v, μ the true
// image. So each squared term (x − r)² becomes (x − r)² − v: the corrected
// MSE is an unbiased estimate of the error against the true image, and
// the corrected relMSE is to first order (its denominator r² + ε is the
// noisy reference's). Trimming chooses its pixels by the raw e_p and then
// averages their corrected terms. MAPE has no such correction (an absolute
// error's expectation does not separate), so it is raw only. Without a
// reference variance (a given EXR) the corrected values equal the raw ones.
#include <string>
#include <vector>
#include "core/image.h"

namespace lb {

struct MetricSettings {
  float relEpsilon = 1e-2f;
  float trimFraction = 1e-3f;  // relmse_trimmed: the share of pixels rejected
};

struct Crop {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // [x0, x1) × [y0, y1); empty = whole image
  bool empty() const { return x1 <= x0 || y1 <= y0; }
};

enum class SquaredError { Mse, RelMse, RelMseTrimmed };

// One squared-error metric of one image: its raw and corrected values, and
// the corrected terms summed per tile of tileSize² pixels (row-major tiles of
// the whole image; tiles outside the region, or wholly trimmed, have count
// 0), for batch-means intervals (experiments/verdict/).
struct SquaredErrorValue {
  double raw = 0, corrected = 0;
  std::vector<double> tileSum, tileCount;  // count: pixels × 3 channels
};
SquaredErrorValue squaredError(const Image& image, const Image& reference, const Image& referenceVariance,
                               SquaredError kind, const MetricSettings& settings, const Crop& crop = {},
                               int tileSize = 8);

// The per-channel weight w of a squared-error metric at a reference value.
inline double squaredErrorWeight(SquaredError kind, double reference, double relEpsilon) {
  return kind == SquaredError::Mse ? 1.0 : 1.0 / (reference * reference + relEpsilon);
}

// Everything the log records of one image (experiments/run_log.h): raw
// values (RMSE, relMSE, trimmed relMSE, MAPE) and the corrected squared
// errors (MSE, not RMSE: a corrected MSE may be negative).
struct ErrorMetrics {
  double rmse = 0, relMse = 0, relMseTrimmed = 0, mape = 0;
  double mseCorrected = 0, relMseCorrected = 0, relMseTrimmedCorrected = 0;
};

// `referenceVariance` may be empty (unknown: corrected = raw).
ErrorMetrics computeMetrics(const Image& image, const Image& reference, const MetricSettings& settings,
                            const Crop& crop = {}, const Image& referenceVariance = {});

// Per-pixel relative squared error (channel mean), for the false-colour image.
Image relativeErrorImage(const Image& image, const Image& reference, float relEpsilon);
// log10 of the error mapped through a perceptual colour ramp (dark blue → yellow),
// over [log10 lo, log10 hi].
Image falseColour(const Image& error, float lo, float hi);
Image cropImage(const Image& image, const Crop& crop, int upscale);

}  // namespace lb
