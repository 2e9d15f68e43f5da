// Metrics on hand-made images whose answers are known in closed form.
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include "experiments/metrics.h"

namespace lb {
namespace {

Image constant(int w, int h, Color c) {
  Image img(w, h);
  for (auto& p : img.pixels) p = c;
  return img;
}

TEST(Metrics, ZeroForIdenticalImages) {
  Image a = constant(4, 3, Color(0.2f, 0.5f, 1.f));
  ErrorMetrics m = computeMetrics(a, a, {});
  EXPECT_EQ(m.rmse, 0);
  EXPECT_EQ(m.relMse, 0);
  EXPECT_EQ(m.mape, 0);
}

TEST(Metrics, KnownValues) {
  // x = r + 0.1 everywhere, r = 1: RMSE = 0.1, relMSE = 0.01/(1 + ε), MAPE = 100·0.1/(1 + ε).
  Image r = constant(5, 5, Color(1.f)), x = constant(5, 5, Color(1.1f));
  MetricSettings s;
  s.relEpsilon = 0.01f;
  ErrorMetrics m = computeMetrics(x, r, s);
  EXPECT_NEAR(m.rmse, 0.1, 1e-6);
  EXPECT_NEAR(m.relMse, 0.01 / 1.01, 1e-6);
  EXPECT_NEAR(m.mape, 100 * 0.1 / 1.01, 1e-4);
}

TEST(Metrics, OneBadPixel) {
  // One pixel of 100 off by 1 in every channel: MSE = 1/100, RMSE = 0.1.
  Image r = constant(10, 10, Color(0.f)), x = r;
  x.at(3, 7) = Color(1.f);
  MetricSettings s;
  s.relEpsilon = 1.f;
  ErrorMetrics m = computeMetrics(x, r, s);
  EXPECT_NEAR(m.rmse, 0.1, 1e-7);
  EXPECT_NEAR(m.relMse, 0.01, 1e-7);  // (1)²/(0 + 1) / 100
  EXPECT_NEAR(m.mape, 1.0, 1e-6);     // 100 · 1/(0 + 1) / 100
  // Trimming 1 % rejects one pixel of 100: the outlier goes.
  s.trimFraction = 0.01f;
  EXPECT_EQ(computeMetrics(x, r, s).relMseTrimmed, 0);
  s.trimFraction = 0.001f;  // 0.1 of a pixel: none is rejected
  EXPECT_NEAR(computeMetrics(x, r, s).relMseTrimmed, 0.01, 1e-7);
}

// relMSE trimmed against a computation written from its definition: the
// per-pixel channel mean of (x − r)²/(r² + ε), sorted, the largest
// floor(n · f) dropped, the rest averaged; random images, several fractions.
TEST(Metrics, TrimmedRelMseAgainstItsDefinition) {
  std::mt19937 rng(3);
  std::lognormal_distribution<float> heavy(-2.f, 1.5f);  // heavy-tailed, as fireflies are
  Image x(37, 23), r(37, 23);
  for (size_t i = 0; i < x.pixels.size(); ++i) x.pixels[i] = Color(heavy(rng), heavy(rng), heavy(rng)), r.pixels[i] = Color(heavy(rng), heavy(rng), heavy(rng));
  for (float fraction : {0.f, 0.001f, 0.01f, 0.1f}) {
    std::vector<double> e;
    for (size_t i = 0; i < x.pixels.size(); ++i) {
      double sum = 0;
      for (int c = 0; c < 3; ++c) {
        double d = double(x.pixels[i][c]) - r.pixels[i][c];
        sum += d * d / (double(r.pixels[i][c]) * r.pixels[i][c] + double(0.01f));  // ε as the float it is
      }
      e.push_back(sum / 3);
    }
    std::sort(e.begin(), e.end());
    size_t keep = e.size() - size_t(std::floor(e.size() * double(fraction) + 1e-6));
    double mean = std::accumulate(e.begin(), e.begin() + keep, 0.0) / double(keep);
    MetricSettings s;
    s.trimFraction = fraction;
    EXPECT_NEAR(computeMetrics(x, r, s).relMseTrimmed, mean, 1e-12 * mean) << fraction;
  }
}

// The corrected squared errors subtract the reference's variance of the mean
// from each squared term: with x − r = 0.3 and a variance of 0.01 in every
// value, MSE 0.09 becomes 0.08 and relMSE (r = 1, ε = 0.01) 0.08/1.01; the
// trimmed one corrects the pixels it keeps. Without a variance: unchanged.
TEST(Metrics, CorrectedForTheReferencesVariance) {
  Image r = constant(6, 4, Color(1.f)), x = constant(6, 4, Color(1.3f)), v = constant(6, 4, Color(0.01f));
  x.at(2, 2) = Color(5.f);  // one firefly, trimmed at 5 %
  MetricSettings s;
  s.trimFraction = 0.05f;
  ErrorMetrics m = computeMetrics(x, r, s, {}, v);
  double mse = (23 * 0.09 + 16.0) / 24;
  EXPECT_NEAR(m.rmse, std::sqrt(mse), 1e-6);
  EXPECT_NEAR(m.mseCorrected, mse - 0.01, 1e-6);
  EXPECT_NEAR(m.relMseCorrected, (mse - 0.01) / 1.01, 1e-6);
  EXPECT_NEAR(m.relMseTrimmed, 0.09 / 1.01, 1e-6);
  EXPECT_NEAR(m.relMseTrimmedCorrected, 0.08 / 1.01, 1e-6);
  ErrorMetrics plain = computeMetrics(x, r, s);
  EXPECT_NEAR(plain.mseCorrected, plain.rmse * plain.rmse, 1e-12);
  EXPECT_EQ(plain.relMseCorrected, plain.relMse);
}

TEST(Metrics, CropSeesOnlyItsRegion) {
  Image r = constant(8, 8, Color(0.f)), x = r;
  x.at(0, 0) = Color(2.f);
  Crop inside{0, 0, 2, 2}, outside{4, 4, 8, 8};
  EXPECT_NEAR(computeMetrics(x, r, {}, inside).rmse, std::sqrt(4.0 / 4), 1e-6);
  EXPECT_EQ(computeMetrics(x, r, {}, outside).rmse, 0);
}

TEST(Metrics, ChannelsAreAveraged) {
  Image r = constant(1, 1, Color(0.f)), x = constant(1, 1, Color(0.3f, 0.f, 0.f));
  EXPECT_NEAR(computeMetrics(x, r, {}).rmse, std::sqrt(0.09 / 3), 1e-7);
}

}  // namespace
}  // namespace lb
