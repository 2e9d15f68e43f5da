// The feature-guided NL-means denoiser (core/denoise.h; Rousselle, Manzi,
// Zwicker 2013): it leaves a noise-free constant image exactly as it is, it
// lowers the error of a noisy Cornell box against an independent reference by
// more than the reference's own noise could explain, a window of one pixel is
// the identity, and non-finite or mismatched input is handled as documented.
#include <gtest/gtest.h>
#include <cmath>
#include <limits>
#include <stdexcept>
#include "core/aov.h"
#include "core/denoise.h"
#include "tests/support/render_helpers.h"
#include "tests/support/statistics.h"

namespace lb::test {
namespace {

// A constant colour with zero variance: every colour distance is 0/ε = 0, so
// the weights are the feature weights alone, which vary with the scene's
// features (walls, boxes, edges). Whatever they are, the output is
// Σ w_k c / Σ w_k over at most 441 weights in (0, 1], with the sums in double:
// the products and the two sums of positive terms carry a relative error of
// at most about 2 · 442 · 2⁻⁵³ ≈ 1e-13 (Higham's γ_n bound), far below half
// a float ulp (at least 2⁻²⁵ relative), so rounding to float returns c
// itself. Hence the bound used: exact equality, 0 ulp.
TEST(Denoise, ConstantNoiseFreeImageIsUnchanged) {
  SceneFile sf = loadShippedScene("cornell-box", 32, 32);
  FirstHitImages features = renderFirstHitImages(*sf.scene, 4, 1);
  // The test means something only if the features vary across the image.
  size_t distinctNormals = 0;
  for (const Color& n : features.normal.pixels) distinctNormals += n != features.normal.pixels[0];
  ASSERT_GT(distinctNormals, 0u);

  const Color constant(0.3f, 0.55f, 17.1f);
  Image color(32, 32), variance(32, 32);  // variance: all zero
  for (Color& c : color.pixels) c = constant;
  Image out = denoiseNlMeans(color, variance, features);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) ASSERT_EQ(out.at(x, y), constant) << "pixel " << x << "," << y;
}

// Honest comparison against a reference that is itself noisy. With t the
// path tracer's expectation and e = reference − t (a different seed: zero mean,
// independent of the noisy render and of everything computed from it), the
// measured error of an image x is
//   MSE(x) = mean((x − t)²) − 2 mean((x − t) e) + mean(e²).
// mean(e²) is the same number for the raw and the denoised image (the same
// reference), so it cancels from their difference, which is
//   MSE(raw) − MSE(den) = [true difference] + 2 mean((den − raw) e).
// The last term has mean 0 and, pixels being independent (independent
// sampler) and a pixel's channels at worst fully correlated (Cauchy–Schwarz),
// variance at most (2/N)² Σ_pixels (Σ_c |den_c − raw_c| σ_c)², with σ_c² the
// reference's variance of the mean. Requiring MSE(den) + z·that deviation <
// MSE(raw) (z two-sided at 1%, used one-sided) therefore says the denoised
// image is closer to the truth than the raw one, not merely closer to this
// reference. (The reference's noise also adds about mean(σ²) to both RMSEs;
// it is printed for scale.)
//
// To see the test fail on purpose: take max(w_c, w_f) instead of the min in
// denoise.cpp. The lamp has the ceiling's albedo, normal and (within 1%)
// depth, so only w_c keeps its ~30 pixels of radiance (17, 12, 4) apart from
// the ceiling's ≈ 0.4; averaging the two along the lamp's rows adds, by our
// estimate (not measured), ≈ 0.5 to the denoised MSE against a raw MSE of
// ≈ 0.06. Scaling the output by 1.05 would NOT be caught: it adds about
// 0.05² · mean(u²) ≈ 0.0025 · 1.3 ≈ 0.003 (mean(u²) is mostly the lamp's,
// 30/4096 · 150 ≈ 1.1, plus ≈ 0.2 from the walls), well inside the margin;
// a factor 2 would (it adds ≈ 1.3). These figures are estimates from the
// scene's geometry and emission, not measurements.
TEST(Denoise, LowersTheErrorOfANoisyCornellBox) {
  SceneFile sf = loadShippedScene("cornell-box", 64, 64);
  auto noisy = renderScene(sf, {"path", "{}", 8, 1});
  auto reference = renderScene(sf, {"path", "{}", 1024, 2});
  FirstHitImages features = renderFirstHitImages(*sf.scene, 16, 3);
  Image raw = noisy->image();
  Image denoised = denoiseNlMeans(raw, noisy->varianceOfMean(), features);
  Image ref = reference->image(), refVariance = reference->varianceOfMean();

  const double n = 3.0 * raw.pixels.size();
  double mseRaw = 0, mseDenoised = 0, referenceNoise = 0, crossVariance = 0;
  for (size_t i = 0; i < raw.pixels.size(); ++i) {
    double crossTerm = 0;  // Σ_c |den_c − raw_c| σ_c for this pixel
    for (int c = 0; c < 3; ++c) {
      double r = ref.pixels[i][c];
      mseRaw += std::pow(raw.pixels[i][c] - r, 2) / n;
      mseDenoised += std::pow(denoised.pixels[i][c] - r, 2) / n;
      referenceNoise += refVariance.pixels[i][c] / n;
      double change = std::abs(double(denoised.pixels[i][c]) - raw.pixels[i][c]);
      crossTerm += change * std::sqrt(double(refVariance.pixels[i][c]));
    }
    crossVariance += std::pow(2 * crossTerm / n, 2);
  }
  double margin = normalCritical(0.01) * std::sqrt(crossVariance);
  EXPECT_LT(mseDenoised + margin, mseRaw)
      << "RMSE raw " << std::sqrt(mseRaw) << ", denoised " << std::sqrt(mseDenoised) << ", margin (MSE) " << margin
      << ", the reference's own noise (RMS) " << std::sqrt(referenceNoise);
}

// A window of radius 0 holds only the pixel itself, whose weight with itself
// is exactly 1 (zero feature distance, colour distance <= 0): the output must
// be the input, bit for bit. (Even another positive self-weight w would give
// w·u/w in double, which rounds back to the float u, so what this catches is
// a window reaching beyond p, or p skipped or weighted 0.)
TEST(Denoise, WindowOfOnePixelIsTheIdentity) {
  SceneFile sf = loadShippedScene("cornell-box", 32, 32);
  auto film = renderScene(sf, {"path", "{}", 4, 5});
  FirstHitImages features = renderFirstHitImages(*sf.scene, 4, 6);
  DenoiseSettings settings;
  settings.windowRadius = 0;
  Image raw = film->image();
  Image out = denoiseNlMeans(raw, film->varianceOfMean(), features, settings);
  ASSERT_EQ(out.width, raw.width);
  ASSERT_EQ(out.height, raw.height);
  for (size_t i = 0; i < raw.pixels.size(); ++i) ASSERT_EQ(out.pixels[i], raw.pixels[i]) << "pixel index " << i;
}

// Non-finite colours or variances are skipped as neighbours and never reach
// the output; the pixel that held them gets the mean of its usable neighbours.
TEST(Denoise, NonFiniteInputNeverReachesTheOutput) {
  SceneFile sf = loadShippedScene("cornell-box", 24, 24);
  auto film = renderScene(sf, {"path", "{}", 4, 7});
  FirstHitImages features = renderFirstHitImages(*sf.scene, 4, 8);
  Image color = film->image(), variance = film->varianceOfMean();
  color.at(12, 12) = Color(std::numeric_limits<float>::quiet_NaN(), 0.5f, 0.5f);
  color.at(3, 20) = Color(Infinity);
  variance.at(20, 4) = Color(Infinity);
  Image out = denoiseNlMeans(color, variance, features);
  for (size_t i = 0; i < out.pixels.size(); ++i) ASSERT_TRUE(isFinite(out.pixels[i])) << "pixel index " << i;
  // The NaN pixel takes the mean of its neighbours, and every surface in the box is lit.
  EXPECT_GT(maxComponent(out.at(12, 12)), 0.f);
}

TEST(Denoise, RefusesMismatchedSizesAndUnknownVariance) {
  SceneFile sf = loadShippedScene("cornell-box", 8, 8);
  FirstHitImages features = renderFirstHitImages(*sf.scene, 1, 1);
  Image color(8, 8), variance(8, 8);
  EXPECT_THROW(denoiseNlMeans(color, Image(8, 7), features), std::invalid_argument);
  EXPECT_THROW(denoiseNlMeans(Image(7, 8), variance, features), std::invalid_argument);
  Image unknown = variance;
  unknown.at(2, 3).g = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(denoiseNlMeans(color, unknown, features), std::invalid_argument);
  DenoiseSettings badTau;
  badTau.tau = 0;
  EXPECT_THROW(denoiseNlMeans(color, variance, features, badTau), std::invalid_argument);
  EXPECT_NO_THROW(denoiseNlMeans(color, variance, features));
}

}  // namespace
}  // namespace lb::test
