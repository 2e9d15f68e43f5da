#include "experiments/metrics.h"
#include <algorithm>
#include <vector>

namespace lb {

namespace {
// Mean of per-pixel values, dropping those above the percentile if asked.
double robustMean(std::vector<double> values, float percentile) {
  if (values.empty()) return 0;
  if (percentile > 0 && percentile < 100) {
    size_t keep = std::max<size_t>(1, size_t(std::ceil(values.size() * percentile / 100.0)));
    std::nth_element(values.begin(), values.begin() + (keep - 1), values.end());
    values.resize(keep);
  }
  double sum = 0;
  for (double v : values) sum += v;
  return sum / double(values.size());
}
}  // namespace

ErrorMetrics computeMetrics(const Image& x, const Image& r, const MetricSettings& s, const Crop& crop) {
  Crop c = crop.empty() ? Crop{0, 0, x.width, x.height} : crop;
  std::vector<double> se, rel, ape;
  size_t n = size_t(c.x1 - c.x0) * size_t(c.y1 - c.y0);
  se.reserve(n), rel.reserve(n), ape.reserve(n);
  const double eps = s.relEpsilon;
  for (int y = c.y0; y < c.y1; ++y)
    for (int px = c.x0; px < c.x1; ++px) {
      double a = 0, b = 0, d = 0;
      for (int ch = 0; ch < 3; ++ch) {
        double xv = x.at(px, y)[ch], rv = r.at(px, y)[ch], diff = xv - rv;
        a += diff * diff;
        b += diff * diff / (rv * rv + eps);
        d += std::abs(diff) / (std::abs(rv) + eps);
      }
      se.push_back(a / 3), rel.push_back(b / 3), ape.push_back(d / 3);
    }
  ErrorMetrics m;
  m.rmse = std::sqrt(robustMean(se, s.outlierPercentile));
  m.relMse = robustMean(rel, s.outlierPercentile);
  m.mape = 100 * robustMean(ape, s.outlierPercentile);
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
