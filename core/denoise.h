#pragma once
// Feature-guided non-local-means denoising of a rendered image: Rousselle,
// Manzi, Zwicker 2013, "Robust Denoising using Feature and Color Information"
// (Pacific Graphics 2013, Computer Graphics Forum 32(7)). What is kept from
// the paper and what is simplified is explained at the top of denoise.cpp.
#include "core/aov.h"
#include "core/image.h"

namespace lb {

struct DenoiseSettings {
  int windowRadius = 10;   // r: each pixel averages the (2r+1)² pixels around it (paper: 10)
  int patchRadius = 3;     // f: colours are compared over (2f+1)² patches (paper: 3)
  float kColor = 0.45f;    // k_c: sensitivity to colour differences, in noise deviations (paper: 0.45)
  float kFeature = 0.6f;   // k_f: sensitivity to feature differences (paper: 0.6)
  float tau = 1e-3f;       // τ: floor of a feature's squared gradient (paper: 1e-3)
  float epsilon = 1e-10f;  // ε: keeps the colour distance finite where the variance is zero
};

// The filtered image. `varianceOfMean` is the per-pixel, per-channel variance
// of the pixel estimate (Film::varianceOfMean()); `features` are the first-hit
// images of the same camera (renderFirstHitImages). Throws
// std::invalid_argument when the sizes disagree, when a setting is out of
// range, or when `varianceOfMean` holds a NaN ("variance unknown", e.g. a
// Markov chain's passes): the colour distance is measured in units of that
// variance, so without it the filter has no scale to work with.
// Non-finite colours never reach the output (see denoise.cpp). The result
// does not depend on the thread count. A variance of 0 (a film pixel with one
// sample) reads as noise-free: no neighbour with another colour is averaged in.
Image denoiseNlMeans(const Image& color, const Image& varianceOfMean, const FirstHitImages& features,
                     const DenoiseSettings& settings = {});

}  // namespace lb
