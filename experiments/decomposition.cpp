#include "experiments/decomposition.h"
#include <cmath>
#include <stdexcept>

namespace lb {

namespace {
// Per-tile sums, for the batch-means interval.
struct Tile {
  double bias2 = 0, variance = 0, mse = 0, referenceVariance = 0;
  double count = 0;
};

// Mean over tiles weighted by their pixel counts, and its 95 % interval.
void weightedMean(const std::vector<Tile>& tiles, double Tile::*field, double* mean, double* low, double* high) {
  double n = 0, sum = 0;
  for (const auto& t : tiles) n += t.count, sum += t.*field;
  *mean = sum / n;
  // Batch means: each tile's mean x_i, weighted by its share w_i of the
  // pixels (edge tiles are smaller). The ratio estimator's variance,
  // k/(k−1) Σ w_i² (x_i − mean)², reduces to s²/k for equal tiles.
  double var = 0, k = 0;
  for (const auto& t : tiles) {
    if (t.count == 0) continue;
    double w = t.count / n, d = t.*field / t.count - *mean;
    var += w * w * d * d;
    k += 1;
  }
  double se = k > 1 ? std::sqrt(var * k / (k - 1)) : INFINITY;
  *low = *mean - 1.96 * se;
  *high = *mean + 1.96 * se;
}
}  // namespace

ErrorDecomposition decomposeError(const std::vector<Image>& finals, const Image& reference,
                                  const Image& referenceVariance, int tileSize) {
  if (finals.size() < 2) throw std::invalid_argument("decomposeError needs two repeats at least");
  const int w = reference.width, h = reference.height;
  const double R = double(finals.size());
  const bool knownReference = !referenceVariance.pixels.empty();
  int tilesX = (w + tileSize - 1) / tileSize, tilesY = (h + tileSize - 1) / tileSize;
  std::vector<Tile> tiles(size_t(tilesX) * tilesY);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      Tile& t = tiles[size_t(y / tileSize) * tilesX + x / tileSize];
      for (int c = 0; c < 3; ++c) {
        double ref = reference.at(x, y)[c];
        double mean = 0, mse = 0;
        for (const auto& f : finals) {
          double v = f.at(x, y)[c];
          mean += v;
          mse += (v - ref) * (v - ref);
        }
        mean /= R;
        double s2 = 0;
        for (const auto& f : finals) s2 += (f.at(x, y)[c] - mean) * (f.at(x, y)[c] - mean);
        s2 /= R - 1;  // unbiased: one run's variance
        double refVar = knownReference ? double(referenceVariance.at(x, y)[c]) : 0.0;
        // E[(mean − ref)²] = bias² + variance / R + reference variance.
        t.bias2 += (mean - ref) * (mean - ref) - s2 / R - refVar;
        t.variance += s2;
        t.mse += mse / R;
        t.referenceVariance += refVar;
        t.count += 1;
      }
    }
  ErrorDecomposition d;
  d.repeats = int(finals.size());
  double low, high;
  weightedMean(tiles, &Tile::mse, &d.mse, &low, &high);
  weightedMean(tiles, &Tile::referenceVariance, &d.referenceVariance, &low, &high);
  weightedMean(tiles, &Tile::bias2, &d.bias2, &d.bias2Low, &d.bias2High);
  weightedMean(tiles, &Tile::variance, &d.variance, &d.varianceLow, &d.varianceHigh);
  if (!knownReference) d.referenceVariance = NAN;  // and bias² includes it
  return d;
}

}  // namespace lb
