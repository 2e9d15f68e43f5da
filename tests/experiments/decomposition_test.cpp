// The bias²/variance split of a configuration's final error over repeats,
// on synthetic images whose bias, noise and reference noise are known.
#include "experiments/decomposition.h"
#include <gtest/gtest.h>
#include <cmath>
#include <random>

namespace lb {
namespace {

struct Synthetic {
  std::vector<Image> finals;
  Image reference, referenceVariance;
};

// True image t(x, y); each run = t + bias + N(0, sigma²); the reference =
// t + N(0, refSigma²) with its variance image exact.
Synthetic synthetic(int repeats, double bias, double sigma, double refSigma, uint32_t seed) {
  const int w = 128, h = 96;
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Synthetic s;
  Image truth(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) truth.at(x, y) = Color(0.2f + 0.6f * float(x) / w, 0.5f, 0.8f - 0.5f * float(y) / h);
  s.reference = Image(w, h);
  s.referenceVariance = Image(w, h);
  for (size_t i = 0; i < truth.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      s.reference.pixels[i][c] = float(truth.pixels[i][c] + refSigma * normal(rng));
      s.referenceVariance.pixels[i][c] = float(refSigma * refSigma);
    }
  for (int r = 0; r < repeats; ++r) {
    Image run(w, h);
    for (size_t i = 0; i < truth.pixels.size(); ++i)
      for (int c = 0; c < 3; ++c) run.pixels[i][c] = float(truth.pixels[i][c] + bias + sigma * normal(rng));
    s.finals.push_back(run);
  }
  return s;
}

// Each estimate lies within its interval, widened from 1.96 to 4 standard
// errors (a fixed seed: the test must not fail by chance), of the truth.
void expectWithin(double estimate, double low, double high, double truth, const char* what) {
  double se = (high - low) / (2 * 1.96);
  EXPECT_LT(std::abs(estimate - truth), 4 * se) << what << ": " << estimate << " [" << low << ", " << high
                                                << "], truth " << truth;
  EXPECT_LT(se, 0.1 * truth) << what << ": the interval must be narrow enough to tell the terms apart";
}

TEST(ErrorDecomposition, RecoversKnownBiasAndVarianceWithANoisyReference) {
  for (int repeats : {2, 5}) {
    Synthetic s = synthetic(repeats, 0.03, 0.1, 0.05, 17 + repeats);
    ErrorDecomposition d = decomposeError(s.finals, s.reference, s.referenceVariance);
    EXPECT_EQ(d.repeats, repeats);
    expectWithin(d.bias2, d.bias2Low, d.bias2High, 0.03 * 0.03, "bias²");
    expectWithin(d.variance, d.varianceLow, d.varianceHigh, 0.1 * 0.1, "variance");
    EXPECT_NEAR(d.referenceVariance, 0.05 * 0.05, 1e-9);
    // Algebra, not statistics: the terms add up to the mean MSE over repeats.
    EXPECT_NEAR(d.mse, d.bias2 + d.variance + d.referenceVariance, 1e-9 * d.mse);
  }
}

// An unbiased method: bias² is zero within its interval, although its MSE is
// all noise (of the runs and of the reference).
TEST(ErrorDecomposition, AnUnbiasedMethodHasNoBias) {
  Synthetic s = synthetic(3, 0.0, 0.1, 0.05, 5);
  ErrorDecomposition d = decomposeError(s.finals, s.reference, s.referenceVariance);
  EXPECT_LE(d.bias2Low, 0.0);
  EXPECT_GE(d.bias2High, 0.0);
  EXPECT_LT(d.bias2High - d.bias2Low, 0.05 * d.mse);
}

// Against a given EXR the reference's variance is unknown: it is reported as
// such (NaN) and bias² includes it.
TEST(ErrorDecomposition, AnUnknownReferenceVarianceIsInBias) {
  Synthetic s = synthetic(3, 0.03, 0.1, 0.05, 9);
  ErrorDecomposition d = decomposeError(s.finals, s.reference, Image());
  EXPECT_TRUE(std::isnan(d.referenceVariance));
  expectWithin(d.bias2, d.bias2Low, d.bias2High, 0.03 * 0.03 + 0.05 * 0.05, "bias² with the reference's variance");
}

TEST(ErrorDecomposition, NeedsTwoRepeats) {
  Synthetic s = synthetic(1, 0.0, 0.1, 0.0, 1);
  EXPECT_THROW(decomposeError(s.finals, s.reference, s.referenceVariance), std::invalid_argument);
}

}  // namespace
}  // namespace lb
