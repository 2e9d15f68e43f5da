#include "integrators/bdpt/bdpt.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <filesystem>

namespace lb {

BdptSettings BdptSettings::read(Params& p) {
  BdptSettings s;
  s.length = PathLength::read(p);
  std::string mis = p.getChoice("mis", "power", {"power", "balance", "uniform"});
  s.mis = mis == "power" ? MisWeighting::Power : mis == "balance" ? MisWeighting::Balance : MisWeighting::Uniform;
  s.strategyImages = p.getInt("strategy_images", 0);
  if (s.strategyImages < 0 || s.strategyImages > 8) p.fail("strategy_images", "must be in [0, 8] (path length in segments)");
  p.checkUnused();
  return s;
}

namespace {
constexpr int TileSize = 16;

struct StrategySplat {
  int strategy;
  Splat weighted, unweighted;
};
}  // namespace

int Bdpt::strategyIndex(int s, int t) const {
  for (size_t i = 0; i < strategies_.size(); ++i)
    if (strategies_[i] == std::make_pair(s, t)) return int(i);
  return -1;
}

void Bdpt::renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass, PassStats& stats) {
  const int W = film.width(), H = film.height();
  if (settings_.strategyImages > 0 && strategies_.empty())
    for (int len = 1; len <= settings_.strategyImages; ++len)
      for (int t = 1; t <= len + 1; ++t) {
        int s = len + 1 - t;
        if (s == 1 && t == 1) continue;  // covered by s = 0, t = 2 (pbrt-v3)
        strategies_.push_back({s, t});
        weighted_.push_back(std::make_unique<Film>(W, H));
        unweighted_.push_back(std::make_unique<Film>(W, H));
      }
  std::vector<PassImage> strategyPass, strategyPassRaw;
  for (size_t i = 0; i < strategies_.size(); ++i) strategyPass.emplace_back(W, H), strategyPassRaw.emplace_back(W, H);

  int tilesX = (W + TileSize - 1) / TileSize, tilesY = (H + TileSize - 1) / TileSize;
  std::vector<std::vector<Splat>> splats(size_t(tilesX * tilesY));
  std::vector<std::vector<StrategySplat>> strategySplats(size_t(tilesX * tilesY));
  PassImage image(W, H);
  int maxSeg = settings_.length.maxSegments();
  // "Unlimited" depth is capped at 4096 segments: the subpaths' arrays.
  size_t cameraCapacity = size_t(std::min(maxSeg, 1 << 12)) + 1, lightCapacity = std::max<size_t>(1, cameraCapacity - 1);

  tbb::parallel_for(tbb::blocked_range<int>(0, tilesX * tilesY), [&](const tbb::blocked_range<int>& range) {
    auto sampler = prototype.clone();
    std::vector<bdpt::Vertex> camera(cameraCapacity), light(lightCapacity);
    uint64_t rays = 0;
    for (int tile = range.begin(); tile != range.end(); ++tile) {
      int x0 = (tile % tilesX) * TileSize, y0 = (tile / tilesX) * TileSize;
      for (int y = y0; y < std::min(y0 + TileSize, H); ++y)
        for (int x = x0; x < std::min(x0 + TileSize, W); ++x) {
          sampler->start(uint64_t(y) * W + x, pass);
          Vec2 raster = Vec2(x, y) + sampler->get2D();
          int nCamera = bdpt::generateCameraSubpath(scene, *sampler, settings_, raster, camera, rays);
          int nLight = bdpt::generateLightSubpath(scene, *sampler, settings_, light, rays);
          Color L(0.f);
          for (int t = 1; t <= nCamera; ++t)
            for (int s = 0; s <= nLight; ++s) {
              int segments = s + t - 1;
              if ((s == 1 && t == 1) || segments < 1 || segments > maxSeg) continue;
              bdpt::Connection c = bdpt::connect(scene, *sampler, settings_, light, camera, s, t, rays);
              if (isBlack(c.L) || c.weight == 0) continue;
              Color weighted = c.L * c.weight;
              if (!isFinite(weighted)) {  // counted and dropped alone, not with the whole pixel
                film.recordNonFinite(x, y, pass);
                continue;
              }
              if (t == 1) splats[size_t(tile)].push_back({c.raster, weighted});
              else L += weighted;
              int k = strategies_.empty() ? -1 : strategyIndex(s, t);
              if (k >= 0) {
                Vec2 at = t == 1 ? c.raster : Vec2(x, y);
                strategySplats[size_t(tile)].push_back({k, {at, weighted}, {at, c.L}});
              }
            }
          image.add(x, y, L, pass, film);  // this tile owns pixel (x, y)
        }
    }
    stats.rays += rays;
  });
  for (const auto& tileSplats : splats)  // fixed order: deterministic sums
    for (const Splat& s : tileSplats) image.addAtRaster(s.raster, s.value, pass, film);
  film.addPass(image);
  if (!strategies_.empty()) {
    for (const auto& tileSplats : strategySplats)
      for (const StrategySplat& s : tileSplats) {
        strategyPass[size_t(s.strategy)].addAtRaster(s.weighted.raster, s.weighted.value, pass, *weighted_[size_t(s.strategy)]);
        strategyPassRaw[size_t(s.strategy)].addAtRaster(s.unweighted.raster, s.unweighted.value, pass, *unweighted_[size_t(s.strategy)]);
      }
    for (size_t i = 0; i < strategies_.size(); ++i) weighted_[i]->addPass(strategyPass[i]), unweighted_[i]->addPass(strategyPassRaw[i]);
  }
}

std::vector<std::string> Bdpt::writeExtraOutputs(const std::string& stem) const {
  std::vector<std::string> written;
  for (size_t i = 0; i < strategies_.size(); ++i) {
    auto [s, t] = strategies_[i];
    std::string base = stem + "_s" + std::to_string(s) + "_t" + std::to_string(t);
    for (auto [film, suffix] : {std::pair{weighted_[i].get(), ""}, std::pair{unweighted_[i].get(), "_unweighted"}}) {
      Image img = film->image();
      writeExr(base + suffix + ".exr", img);
      writePng(base + suffix + ".png", img);
      written.push_back(base + suffix + ".exr");
    }
  }
  return written;
}

}  // namespace lb
