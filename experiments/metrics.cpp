#include "experiments/metrics.h"
#include <algorithm>
#include <cmath>
#include <vector>

namespace lb {

namespace {

bool hasVariance(const Image& v, const Image& x) { return v.width == x.width && v.height == x.height && !v.pixels.empty(); }

}  // namespace

SquaredErrorValue squaredError(const Image& x, const Image& r, const Image& v, SquaredError kind,
                               const MetricSettings& s, const Crop& crop, int tileSize) {
  const Crop c = crop.empty() ? Crop{0, 0, x.width, x.height} : crop;
  const bool corrected = hasVariance(v, x);
  const int tilesX = (x.width + tileSize - 1) / tileSize, tilesY = (x.height + tileSize - 1) / tileSize;
  SquaredErrorValue out;
  out.tileSum.assign(size_t(tilesX) * tilesY, 0.0);
  out.tileCount.assign(out.tileSum.size(), 0.0);
  // Per pixel: the raw and corrected channel means, and its tile.
  struct Term {
    double raw, corrected;
    size_t tile;
  };
  std::vector<Term> terms;
  terms.reserve(size_t(c.x1 - c.x0) * size_t(c.y1 - c.y0));
  for (int py = c.y0; py < c.y1; ++py)
    for (int px = c.x0; px < c.x1; ++px) {
      double raw = 0, cor = 0;
      for (int ch = 0; ch < 3; ++ch) {
        double rv = r.at(px, py)[ch], diff = double(x.at(px, py)[ch]) - rv;
        double w = squaredErrorWeight(kind, rv, s.relEpsilon);
        raw += w * diff * diff;
        cor += w * (diff * diff - (corrected ? double(v.at(px, py)[ch]) : 0.0));
      }
      terms.push_back({raw / 3, cor / 3, size_t(py / tileSize) * tilesX + size_t(px / tileSize)});
    }
  if (terms.empty()) return out;
  if (kind == SquaredError::RelMseTrimmed && s.trimFraction > 0) {
    // Keep the smallest raw terms: the rejected pixels are chosen by what
    // the run shows (its fireflies), the kept ones then corrected.
    // (+1e-6: a fraction written 0.01 is the float 0.0099999998.)
    size_t reject = std::min(terms.size() - 1, size_t(std::floor(double(terms.size()) * s.trimFraction + 1e-6)));
    size_t keep = terms.size() - reject;
    std::nth_element(terms.begin(), terms.begin() + (keep - 1), terms.end(),
                     [](const Term& a, const Term& b) { return a.raw < b.raw; });
    terms.resize(keep);
  }
  double raw = 0, cor = 0;
  for (const Term& t : terms) {
    raw += t.raw, cor += t.corrected;
    out.tileSum[t.tile] += 3 * t.corrected;
    out.tileCount[t.tile] += 3;
  }
  out.raw = raw / double(terms.size());
  out.corrected = cor / double(terms.size());
  return out;
}

ErrorMetrics computeMetrics(const Image& x, const Image& r, const MetricSettings& s, const Crop& crop,
                            const Image& variance) {
  ErrorMetrics m;
  SquaredErrorValue mse = squaredError(x, r, variance, SquaredError::Mse, s, crop);
  SquaredErrorValue rel = squaredError(x, r, variance, SquaredError::RelMse, s, crop);
  SquaredErrorValue trimmed = squaredError(x, r, variance, SquaredError::RelMseTrimmed, s, crop);
  m.rmse = std::sqrt(mse.raw), m.mseCorrected = mse.corrected;
  m.relMse = rel.raw, m.relMseCorrected = rel.corrected;
  m.relMseTrimmed = trimmed.raw, m.relMseTrimmedCorrected = trimmed.corrected;
  const Crop c = crop.empty() ? Crop{0, 0, x.width, x.height} : crop;
  double ape = 0;
  for (int y = c.y0; y < c.y1; ++y)
    for (int px = c.x0; px < c.x1; ++px)
      for (int ch = 0; ch < 3; ++ch) {
        double rv = r.at(px, y)[ch];
        ape += std::abs(double(x.at(px, y)[ch]) - rv) / (std::abs(rv) + s.relEpsilon);
      }
  size_t n = size_t(c.x1 - c.x0) * size_t(c.y1 - c.y0) * 3;
  m.mape = n ? 100 * ape / double(n) : 0;
  return m;
}

Image relativeErrorImage(const Image& x, const Image& r, float eps) {
  Image e(x.width, x.height);
  for (size_t i = 0; i < x.pixels.size(); ++i) {
    Color d = x.pixels[i] - r.pixels[i];
    Color rel = d * d / (r.pixels[i] * r.pixels[i] + Color(eps));
    e.pixels[i] = Color((rel.r + rel.g + rel.b) / 3);
  }
  return e;
}

Image falseColour(const Image& error, float lo, float hi) {
  // Five stops of matplotlib's viridis, linearised for the sRGB PNG writer.
  const Color stops[5] = {{0.267f, 0.005f, 0.329f}, {0.230f, 0.322f, 0.546f}, {0.128f, 0.567f, 0.551f},
                          {0.369f, 0.789f, 0.383f}, {0.993f, 0.906f, 0.144f}};
  Image out(error.width, error.height);
  float l0 = std::log10(lo), l1 = std::log10(hi);
  for (size_t i = 0; i < error.pixels.size(); ++i) {
    float e = error.pixels[i].r;
    float v = std::isfinite(e) ? std::log10(std::max(e, 1e-30f)) : l1;  // non-finite: the top colour
    float t = glm::clamp((v - l0) / (l1 - l0), 0.f, 1.f) * 4;
    int k = std::min(3, int(t));
    Color c = glm::mix(stops[k], stops[k + 1], t - k);
    out.pixels[i] = glm::pow(c, Color(2.2f));
  }
  return out;
}

Image cropImage(const Image& img, const Crop& c, int upscale) {
  Image out((c.x1 - c.x0) * upscale, (c.y1 - c.y0) * upscale);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) out.at(x, y) = img.at(c.x0 + x / upscale, c.y0 + y / upscale);
  return out;
}

}  // namespace lb
