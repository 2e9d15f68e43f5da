// Metrics on hand-made images whose answers are known in closed form.
#include <gtest/gtest.h>
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
  // The 99th percentile keeps 99 of the 100 pixels: the outlier goes.
  s.outlierPercentile = 99;
  EXPECT_EQ(computeMetrics(x, r, s).rmse, 0);
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
