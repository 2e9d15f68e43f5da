#pragma once
// A configuration's final error split over its repeats (issue 13): the mean
// squared error against the reference is, in expectation,
//     MSE = bias² + variance + reference variance,
// where `variance` is one run's noise (the spread of the repeats around their
// mean) and `bias²` what is left of the mean's squared error once its
// expected noise (variance / repeats) and the reference's own variance are
// taken out. An unbiased method has bias² ≈ 0 at any time; a consistent one
// (photon mapping, SPPM, VCM's merging) shows its error floor there.
//
// Over all pixels and colour channels, without the metrics' outlier
// trimming. Confidence intervals: 95 %, treating 8×8-pixel tiles as batch
// means (normal approximation over tiles). That counts the spatial variation
// of the error as if it were noise, so the intervals are conservative.
#include <vector>
#include "core/image.h"

namespace lb {

struct ErrorDecomposition {
  int repeats = 0;
  double mse = 0;  // mean over repeats of each run's MSE
  double bias2 = 0, bias2Low = 0, bias2High = 0;
  double variance = 0, varianceLow = 0, varianceHigh = 0;
  // The reference's mean variance of the mean; NaN if unknown (a given EXR,
  // a one-chunk reference), and then bias² includes it: an upper bound.
  double referenceVariance = 0;
};

// `finals`: each repeat's final image (two at least); `referenceVariance`:
// per-pixel variance of the reference's mean, or an empty image if unknown.
ErrorDecomposition decomposeError(const std::vector<Image>& finals, const Image& reference,
                                  const Image& referenceVariance, int tileSize = 8);

}  // namespace lb
