#pragma once
// The image in 16×16 tiles, processed in parallel: each tile's pixels are
// visited by one thread in scanline order, with a sampler of its own, so a
// pixel's work never depends on thread scheduling. Rays are counted per TBB
// range and added to the pass statistics once.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include "integrators/integrator.h"

namespace lb {

constexpr int TileSize = 16;

inline int tilesAcross(int width) { return (width + TileSize - 1) / TileSize; }
inline int tileCount(int width, int height) { return tilesAcross(width) * ((height + TileSize - 1) / TileSize); }

// perPixel(tile, x, y, sampler, rays) for every pixel of a width × height image.
template <typename PerPixel>
void forEachPixel(int width, int height, const Sampler& prototype, PassStats& stats, const PerPixel& perPixel) {
  int across = tilesAcross(width);
  tbb::parallel_for(tbb::blocked_range<int>(0, tileCount(width, height)), [&](const tbb::blocked_range<int>& range) {
    auto sampler = prototype.clone();
    uint64_t rays = 0;
    for (int tile = range.begin(); tile != range.end(); ++tile) {
      int x0 = (tile % across) * TileSize, y0 = (tile / across) * TileSize;
      for (int y = y0; y < std::min(y0 + TileSize, height); ++y)
        for (int x = x0; x < std::min(x0 + TileSize, width); ++x) perPixel(tile, x, y, *sampler, rays);
    }
    stats.rays += rays;
  });
}

}  // namespace lb
