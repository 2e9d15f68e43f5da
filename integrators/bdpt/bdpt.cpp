#include "integrators/bdpt/bdpt.h"
#include "integrators/bidirectional/all_strategies.h"
#include <filesystem>
#include "integrators/pixel_tiles.h"

namespace lb {

BdptSettings BdptSettings::read(Params& p) {
  BdptSettings s;
  s.length = PathLength::read(p);
  std::string mis = p.getChoice("mis", "power", {"power", "balance", "uniform"},
                                "MIS heuristic over the (s,t) strategies (Veach 1997, 10.2)");
  using bidir::MisWeighting;
  s.mis = mis == "power" ? MisWeighting::Power : mis == "balance" ? MisWeighting::Balance : MisWeighting::Uniform;
  s.strategyImages = p.getInt("strategy_images", 0,
                              {"each strategy's weighted and unweighted image, up to this path length in segments, "
                               "as layers of the EXR; 0: none",
                               Range::between(0, 8)});
  s.regularization = RegularizationSettings::read(p);
  p.checkUnused();
  return s;
}

namespace {
struct StrategySplat {
  int strategy;
  Splat weighted, unweighted;
};
}  // namespace

Bdpt::Bdpt(BdptSettings s) : settings_(s) {
  if (s.regularization.enabled) regularization_ = std::make_unique<Regularization>(s.regularization);
}

int Bdpt::strategyIndex(int s, int t) const {
  for (size_t i = 0; i < strategies_.size(); ++i)
    if (strategies_[i] == std::make_pair(s, t)) return int(i);
  return -1;
}

void Bdpt::renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass, PassStats& stats) {
  const int W = film.width(), H = film.height();
  if (regularization_) regularization_->prepare(scene, pass);  // this pass's roughness, fixed while it renders
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
  const PixelFilter* filter = &scene.camera.filter();
  for (size_t i = 0; i < strategies_.size(); ++i)
    strategyPass.emplace_back(W, H, filter), strategyPassRaw.emplace_back(W, H, filter);

  std::vector<std::vector<Splat>> splats(size_t(tileCount(W, H)));
  std::vector<std::vector<StrategySplat>> strategySplats(size_t(tileCount(W, H)));
  PassImage image(W, H, filter);

  forEachPixel(W, H, prototype, stats, [&](int tile, int x, int y, Sampler& sampler, uint64_t& rays) {
    bidir::PhaseScope phase(bidir::Phase::CameraSubpaths);  // what the scopes within do not claim
    thread_local bidir::SubpathBuffers buffers;
    buffers.fit(settings_.length);
    sampler.start(uint64_t(y) * W + x, pass);
    Camera::FilmSample at = scene.camera.sampleFilm(x, y, sampler.get2D());
    Color L(0.f);
    bidir::sampleAllStrategies(
        scene, {sampler, sampler, sampler, true, regularization_.get()}, settings_.length, settings_.mis, at.raster, buffers, rays,
        [&](int s, int t, const bidir::Connection& c) {
          // A t = 1 strategy is splatted through the filter; the others
          // belong to pixel (x, y) with the camera sample's filter weight.
          Color weighted = t == 1 ? c.L * c.weight : c.L * c.weight * at.weight;
          if (!isFinite(weighted)) {  // counted and dropped alone, not with the whole pixel
            film.recordNonFinite(x, y, pass);
            return;
          }
          if (t == 1) splats[size_t(tile)].push_back({c.raster, weighted});
          else L += weighted;
          int k = strategies_.empty() ? -1 : strategyIndex(s, t);
          if (k >= 0) {
            Vec2 where = t == 1 ? c.raster : Vec2(x, y);
            strategySplats[size_t(tile)].push_back({k, {where, weighted}, {where, t == 1 ? c.L : c.L * at.weight}});
          }
        });
    image.add(x, y, L, pass, film);  // this tile owns pixel (x, y)
  });
  for (const auto& tileSplats : splats)  // fixed order: deterministic sums
    for (const Splat& s : tileSplats) image.splat(s.raster, s.value, pass, film);
  film.addPass(image);
  if (!strategies_.empty()) {
    for (const auto& tileSplats : strategySplats)
      for (const StrategySplat& s : tileSplats) {
        size_t k = size_t(s.strategy);
        if (strategies_[k].second == 1) {  // t = 1: splatted
          strategyPass[k].splat(s.weighted.raster, s.weighted.value, pass, *weighted_[k]);
          strategyPassRaw[k].splat(s.unweighted.raster, s.unweighted.value, pass, *unweighted_[k]);
        } else {
          strategyPass[k].addAtRaster(s.weighted.raster, s.weighted.value, pass, *weighted_[k]);
          strategyPassRaw[k].addAtRaster(s.unweighted.raster, s.unweighted.value, pass, *unweighted_[k]);
        }
      }
    for (size_t i = 0; i < strategies_.size(); ++i) weighted_[i]->addPass(strategyPass[i]), unweighted_[i]->addPass(strategyPassRaw[i]);
  }
}

// Layers "s2_t1" (MIS-weighted) and "s2_t1_unweighted" of the main EXR: the
// weighted ones sum to the image (Veach 1997, Fig. 10.3 shows them side by side).
std::vector<ExrLayer> Bdpt::extraLayers() const {
  std::vector<ExrLayer> layers;
  for (size_t i = 0; i < strategies_.size(); ++i) {
    auto [s, t] = strategies_[i];
    std::string base = "s" + std::to_string(s) + "_t" + std::to_string(t);
    layers.push_back({base, {"R", "G", "B"}, weighted_[i]->image()});
    layers.push_back({base + "_unweighted", {"R", "G", "B"}, unweighted_[i]->image()});
  }
  return layers;
}

}  // namespace lb
