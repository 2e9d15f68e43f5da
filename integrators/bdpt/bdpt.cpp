#include "integrators/bdpt/bdpt.h"
#include "integrators/bidirectional/all_strategies.h"
#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include "integrators/pixel_tiles.h"

namespace lb {

BdptSettings BdptSettings::read(Params& p) {
  BdptSettings s;
  s.length = PathLength::read(p);
  std::string mis = p.getChoice("mis", "power", {"power", "balance", "uniform", "variance_aware"},
                                "MIS heuristic over the (s,t) strategies (Veach 1997, 10.2); variance_aware: the "
                                "balance heuristic scaled by each strategy's learned second moment over variance "
                                "(Grittmann et al. 2019)");
  using bidir::MisWeighting;
  s.mis = mis == "power" ? MisWeighting::Power : mis == "uniform" ? MisWeighting::Uniform : MisWeighting::Balance;
  s.varianceAware = mis == "variance_aware";
  if (s.varianceAware || p.describing()) {
    p.setCondition("mis: variance_aware");
    s.pilotPasses = p.getInt("pilot_passes", 1,
                             {"first passes, weighted by the balance heuristic, whose samples estimate each "
                              "strategy's moments (kept in the image)",
                              Range::between(1, 64)});
    s.factorBlock = std::stoi(p.getChoice("factor_block", "8", {"1", "2", "4", "8", "16"},
                                          "pixels per side of the square blocks over which the moments are pooled"));
    p.setCondition("");
  }
  s.strategyImages = p.getInt("strategy_images", 0,
                              {"each strategy's weighted and unweighted image, up to this path length in segments, "
                               "as layers of the EXR; 0: none",
                               Range::between(0, 8)});
  s.regularization = RegularizationSettings::read(p);
  p.checkUnused();
  if (s.varianceAware && s.regularization.enabled)
    p.fail("mis", "variance_aware learns per-strategy moments of fixed passes; regularize changes the integrand "
                  "pass by pass");
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

void Bdpt::preprocess(const Scene&, const Sampler& prototype) {
  // Learned factors are a function of the earlier passes' numbers; a pass is
  // unbiased under them only if its own numbers are independent of theirs,
  // which a low-discrepancy sequence's are not (as for path's).
  if (settings_.varianceAware && !dynamic_cast<const IndependentSampler*>(&prototype))
    throw std::invalid_argument(
        "bdpt, mis: variance_aware: each pass uses the factors learned from the first passes, so their random "
        "numbers must be independent: use sampler type independent");
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

  // mis: variance_aware: learning (pilot passes) or weighting by the factors.
  if (settings_.varianceAware && !factors_)
    factors_ = std::make_unique<bidir::StrategyFactors>(W, H, settings_.factorBlock);
  bidir::StrategyFactors* learning = factors_ && !factors_->finished() ? factors_.get() : nullptr;
  const bidir::StrategyFactors* weighting = factors_ && factors_->finished() ? factors_.get() : nullptr;
  std::vector<std::vector<LightTracingRecord>> lightTracing(learning ? size_t(tileCount(W, H)) : 0);

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
        scene, {sampler, sampler, sampler, true, regularization_.get(), weighting}, settings_.length, settings_.mis, at.raster, buffers, rays,
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
          if (learning) {  // this pass's unweighted estimate of strategy (s, t) for the pixel
            if (t == 1) lightTracing[size_t(tile)].push_back({c.raster, s, double(luminance(c.L))});
            else learning->record(x, y, s, t, double(luminance(c.L * at.weight)));  // (x, y)'s block is this tile's
          }
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
  if (learning) learnFromLightTracing(lightTracing);
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

void Bdpt::learnFromLightTracing(const std::vector<std::vector<LightTracingRecord>>& records) {
  const int W = factors_->width(), H = factors_->height(), slots = bidir::StrategyFactors::MaxSegments + 1;
  std::vector<double> sums(size_t(W) * size_t(H) * size_t(slots), 0.0);
  for (const auto& tileRecords : records)  // fixed order: deterministic sums
    for (const LightTracingRecord& r : tileRecords) {
      if (r.s >= slots) continue;
      int x = std::clamp(int(r.raster.x), 0, W - 1), y = std::clamp(int(r.raster.y), 0, H - 1);
      sums[(size_t(y) * size_t(W) + size_t(x)) * size_t(slots) + size_t(r.s)] += r.value;
    }
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      for (int s = 2; s < slots; ++s) {
        double v = sums[(size_t(y) * size_t(W) + size_t(x)) * size_t(slots) + size_t(s)];
        if (v != 0) factors_->record(x, y, s, 1, v);
      }
  if (++pilotPassesDone_ >= settings_.pilotPasses) factors_->finish(pilotPassesDone_);
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
