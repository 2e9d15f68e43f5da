#include "experiments/decomposition.h"
#include "experiments/verdict/statistics.h"
#include <cmath>
#include <stdexcept>

namespace lb {

namespace {
// Per-tile sums, for the batch-means interval.
struct Tile {
  double bias2 = 0, variance = 0, mse = 0, referenceVariance = 0;
  double count = 0;
};

// Mean over tiles weighted by their pixel counts, and its 95 % interval
// (batch means, verdict/statistics.h; normal quantile).
void weightedMean(const std::vector<Tile>& tiles, double Tile::*field, double* mean, double* low, double* high) {
  std::vector<double> sums, weights;
  for (const auto& t : tiles) sums.push_back(t.*field), weights.push_back(t.count);
  BatchMeans b = batchMeans(sums, weights);
  double se = std::sqrt(b.varianceOfMean);
  *mean = b.mean;
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
