// Feature-guided non-local means: Rousselle, Manzi, Zwicker 2013, "Robust
// Denoising using Feature and Color Information" (CGF 32(7), Pacific Graphics
// 2013; RMZ13 below), building on Rousselle, Knaus, Zwicker 2012, "Adaptive
// Rendering with Non-Local Means Filtering" (RKZ12) for the colour term.
//
// Each output pixel is a weighted mean of the pixels q in a (2r+1)² window
// around p (Eq. 1):   u'(p) = Σ_q w(p,q) u(q) / Σ_q w(p,q).
// The weight is the smaller of two weights (Eq. 8), so either can reject q:
//  * Colour (Eqs. 2–4): NL-means on (2f+1)² patches, in units of the noise.
//    Two noisy pixels with the same true value differ, squared, by
//    Var(p) + Var(q) on average; subtracting the variance ("variance
//    cancellation") makes such pairs' distance about 0, and dividing by
//    k_c²(Var(p) + Var(q)) measures what is left in noise deviations.
//    min(Var(p), Var(q)) replaces Var(q) in the subtraction so that a bright,
//    noisy neighbour cannot cancel a real difference (RKZ12: no bleeding of
//    bright regions into dark ones).
//  * Features (Eqs. 5–7): a cross-bilateral term on albedo, normal and depth.
//    Each feature's squared difference is divided by k_f² times its squared
//    gradient at p (at least τ): a feature is trusted where it is flat and
//    less where it changes fast (silhouettes, pixels straddling an edge).
//    The most dissimilar feature decides (max over features).
// Features keep edges that the noise hides; colours keep what features cannot
// see (shadows, caustics, a lamp with the ceiling's albedo, normal and depth).
// Equation numbers are as recalled from the paper, not re-checked against the
// published PDF; the symbols (d²_c, Φ²_j, d²_f, w_c, w_f) are the paper's.
//
// Simplified relative to RMZ13 (one filter, one pass):
//  * No dual buffers: the paper splits the samples into two half-buffers to
//    estimate and smooth the variance; we use the film's per-pixel variance of
//    the mean as given.
//  * No feature prefiltering, so the features' residual variance Var_j is 0
//    in Eq. 5; the gradient term is kept (central differences, one-sided at
//    the image border).
//  * No candidate filters, no SURE-based per-pixel selection, no second pass
//    guided by the first pass's output, no adaptive sampling: one filter with
//    the paper's parameters (r = 10, f = 3, k_c = 0.45, k_f = 0.6, τ = 1e-3).
//  * The patch distance is normalised by the offsets actually compared,
//    1/(3·count) instead of 1/(3|P|): patches are clipped at the border and
//    pixels with non-finite values are left out of the comparison.
// Choices of ours, not in the paper:
//  * Depth is divided by the image's largest finite depth, so that the scene's
//    units drop out and one k_f fits all scenes. Albedo (in [0, 1]) and normals
//    (components in [−1, 1]) are used as they are.
//  * A miss (depth 0: every ray of the pixel left the scene; its albedo and
//    normal are 0 too) never averages with a hit (w_f = 0); two misses have
//    equal features and compare by colour only.
//  * A pixel whose colour or variance is non-finite, or whose variance is
//    negative, is "unusable": never a neighbour, and left out of every patch
//    comparison. It still gets an output: the mean of its usable neighbours,
//    weighted by its own features and (clipped) patch; with no patch offset
//    left to compare, w_c = 1 (no colour evidence). A pixel whose weights sum
//    to 0 gets 0, as the film does with non-finite samples. Non-finite feature
//    values read as 0.
//  * A NaN variance means "unknown" (Film::meanVarianceOfMean): refused with
//    std::invalid_argument rather than guessed, since every colour distance
//    is measured in units of it.
// Cost: pixels · (2r+1)² · (2f+1)² (no box-filtering of per-offset distance
// images as a faster implementation would do); one output pixel per task, so
// the result does not depend on the thread count.
#include "core/denoise.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace lb {
namespace {

// Feature channels: albedo R, G, B; normal X, Y, Z; depth.
constexpr int FeatureChannels = 7;
constexpr int FeatureCount = 3;
constexpr int ChannelsOfFeature[FeatureCount] = {3, 3, 1};

struct PixelFeatures {
  std::array<float, FeatureChannels> value{};
  // 1 / (k_f² max(τ, Var_j(p), ‖∇f_j(p)‖²)) per channel, with Var_j = 0 (Eq. 5).
  std::array<double, FeatureChannels> inverseScale{};  // double: finite for any valid k_f, τ
  bool hit = false;
};

std::vector<PixelFeatures> prepareFeatures(const FirstHitImages& f, const DenoiseSettings& s) {
  const int w = f.depth.width, h = f.depth.height;
  float maxDepth = 0;
  for (const Color& d : f.depth.pixels)
    if (std::isfinite(d.r)) maxDepth = std::max(maxDepth, d.r);
  std::vector<PixelFeatures> out(size_t(w) * size_t(h));
  for (size_t i = 0; i < out.size(); ++i) {
    const Color &a = f.albedo.pixels[i], &n = f.normal.pixels[i];
    float depth = maxDepth > 0 ? f.depth.pixels[i].r / maxDepth : 0.f;  // aov.cpp: the same in r, g, b
    out[i].value = {a.r, a.g, a.b, n.x, n.y, n.z, depth};
    for (float& v : out[i].value)
      if (!std::isfinite(v)) v = 0;
    out[i].hit = out[i].value[6] > 0;
  }
  // Squared gradient by central differences; at the border the missing
  // neighbour is replaced by the pixel itself (a one-sided difference).
  const double kf2 = double(s.kFeature) * s.kFeature;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      int x0 = std::max(x - 1, 0), x1 = std::min(x + 1, w - 1);
      int y0 = std::max(y - 1, 0), y1 = std::min(y + 1, h - 1);
      PixelFeatures& p = out[size_t(y) * w + x];
      for (int c = 0; c < FeatureChannels; ++c) {
        auto v = [&](int px, int py) { return out[size_t(py) * w + px].value[c]; };
        float gx = x1 > x0 ? (v(x1, y) - v(x0, y)) / float(x1 - x0) : 0.f;
        float gy = y1 > y0 ? (v(x, y1) - v(x, y0)) / float(y1 - y0) : 0.f;
        p.inverseScale[c] = 1.0 / (kf2 * std::max(s.tau, gx * gx + gy * gy));
      }
    }
  return out;
}

// d²_f(p, q) = max_j Φ²_j(p, q) (Eq. 6), with Φ²_j (Eq. 5) averaged over the
// feature's channels and Var_j = 0: Φ²_j = mean_c (f_c(p) − f_c(q))² / (k_f² max(τ, ‖∇f_c(p)‖²)).
double featureDistance(const PixelFeatures& p, const PixelFeatures& q) {
  if (p.hit != q.hit) return INFINITY;  // a surface and the background: w_f = 0
  double largest = 0;
  for (int j = 0, c = 0; j < FeatureCount; ++j) {
    double sum = 0;
    for (int k = 0; k < ChannelsOfFeature[j]; ++k, ++c) {
      double diff = double(p.value[c]) - q.value[c];
      sum += diff * diff * p.inverseScale[c];
    }
    largest = std::max(largest, sum / ChannelsOfFeature[j]);
  }
  return largest;
}

// The noisy image with its variance, and the patch comparison of Eqs. 2–3.
struct NoisyImage {
  const Image& color;
  const Image& variance;
  std::vector<char> usable;  // finite colour, finite non-negative variance
  int patchRadius;
  double kColor2, epsilon;

  // d²_c(p, q) = 1/(3·count) Σ_n Σ_i [(u_i(p+n) − u_i(q+n))² − (Var_i(p+n) + min(Var_i(p+n), Var_i(q+n)))]
  //                                  / (ε + k_c² (Var_i(p+n) + Var_i(q+n)))
  // over the offsets n with p+n and q+n inside the image and usable. Returns
  // 0 (no evidence against q) when no offset qualifies.
  double colorDistance(int px, int py, int qx, int qy) const {
    const int w = color.width, h = color.height, f = patchRadius;
    const int dx0 = -std::min({f, px, qx}), dx1 = std::min({f, w - 1 - px, w - 1 - qx});
    const int dy0 = -std::min({f, py, qy}), dy1 = std::min({f, h - 1 - py, h - 1 - qy});
    double sum = 0;
    int count = 0;
    for (int dy = dy0; dy <= dy1; ++dy)
      for (int dx = dx0; dx <= dx1; ++dx) {
        size_t a = size_t(py + dy) * w + (px + dx), b = size_t(qy + dy) * w + (qx + dx);
        if (!usable[a] || !usable[b]) continue;
        for (int i = 0; i < 3; ++i) {
          double varP = variance.pixels[a][i], varQ = variance.pixels[b][i];
          double diff = double(color.pixels[a][i]) - color.pixels[b][i];
          sum += (diff * diff - (varP + std::min(varP, varQ))) / (epsilon + kColor2 * (varP + varQ));
        }
        ++count;
      }
    return count ? sum / (3.0 * count) : 0.0;
  }
};

void requireSameSize(const Image& image, const char* name, const Image& color) {
  if (image.width != color.width || image.height != color.height || image.pixels.size() != color.pixels.size())
    throw std::invalid_argument(std::string("denoiseNlMeans: ") + name + " is " + std::to_string(image.width) + "x" +
                                std::to_string(image.height) + ", the colour image " + std::to_string(color.width) +
                                "x" + std::to_string(color.height));
}

void requireSettings(const DenoiseSettings& s) {
  auto fail = [](const std::string& why) { throw std::invalid_argument("denoiseNlMeans: " + why); };
  if (s.windowRadius < 0 || s.patchRadius < 0) fail("windowRadius and patchRadius must be >= 0");
  // k_f, τ and ε divide: zero would turn identical pixels' 0/0 into NaN.
  if (!(s.kFeature > 0) || !std::isfinite(s.kFeature)) fail("kFeature must be finite and > 0");
  if (!(s.tau > 0) || !std::isfinite(s.tau)) fail("tau must be finite and > 0");
  if (!(s.epsilon > 0) || !std::isfinite(s.epsilon)) fail("epsilon must be finite and > 0");
  if (!(s.kColor >= 0) || !std::isfinite(s.kColor)) fail("kColor must be finite and >= 0");
}

}  // namespace

Image denoiseNlMeans(const Image& color, const Image& varianceOfMean, const FirstHitImages& features,
                     const DenoiseSettings& s) {
  if (size_t(color.width) * size_t(color.height) != color.pixels.size())
    throw std::invalid_argument("denoiseNlMeans: the colour image's pixel count does not match its size");
  requireSameSize(varianceOfMean, "varianceOfMean", color);
  requireSameSize(features.albedo, "the albedo image", color);
  requireSameSize(features.normal, "the normal image", color);
  requireSameSize(features.depth, "the depth image", color);
  requireSettings(s);
  for (const Color& v : varianceOfMean.pixels)
    if (std::isnan(v.r) || std::isnan(v.g) || std::isnan(v.b))
      throw std::invalid_argument("denoiseNlMeans: varianceOfMean holds NaN (variance unknown); the filter needs it");

  const int w = color.width, h = color.height, r = s.windowRadius;
  Image out(w, h);
  const std::vector<PixelFeatures> feature = prepareFeatures(features, s);
  NoisyImage noisy{color, varianceOfMean, std::vector<char>(color.pixels.size()), s.patchRadius,
                   double(s.kColor) * s.kColor, double(s.epsilon)};
  for (size_t i = 0; i < color.pixels.size(); ++i) {
    const Color& v = varianceOfMean.pixels[i];
    noisy.usable[i] = isFinite(color.pixels[i]) && isFinite(v) && v.r >= 0 && v.g >= 0 && v.b >= 0;
  }

  tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y)
      for (int x = 0; x < w; ++x) {
        const PixelFeatures& fp = feature[size_t(y) * w + x];
        glm::dvec3 weightedSum(0.0);  // double: the weights may span many orders of magnitude
        double weightSum = 0;
        for (int qy = std::max(0, y - r); qy <= std::min(h - 1, y + r); ++qy)
          for (int qx = std::max(0, x - r); qx <= std::min(w - 1, x + r); ++qx) {
            size_t q = size_t(qy) * w + qx;
            if (!noisy.usable[q]) continue;
            double featureWeight = std::exp(-featureDistance(fp, feature[q]));  // w_f, Eq. 7
            if (featureWeight == 0) continue;  // min(w_c, w_f) is 0 whatever the colours say
            double colorWeight = std::exp(-std::max(0.0, noisy.colorDistance(x, y, qx, qy)));  // w_c, Eq. 4
            double weight = std::min(colorWeight, featureWeight);                               // Eq. 8
            weightedSum += weight * glm::dvec3(color.pixels[q]);
            weightSum += weight;
          }
        // Eq. 1. A usable pixel has weight 1 with itself, so weightSum >= 1 there.
        out.at(x, y) = weightSum > 0 ? Color(weightedSum / weightSum) : Color(0.f);
      }
  });
  return out;
}

}  // namespace lb
