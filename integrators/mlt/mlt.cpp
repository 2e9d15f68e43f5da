#include "integrators/mlt/mlt.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <cmath>
#include <cstdio>
#include "core/progress.h"
#include "integrators/mlt/integrands.h"
#include "integrators/path_estimator/path_estimator.h"

namespace lb {

MltSettings MltSettings::read(Params& p) {
  MltSettings s;
  s.mode = p.getChoice("mode", "pssmlt", {"pssmlt", "mmlt"},
                       "pssmlt: Kelemen et al. 2002 over one base estimator; mmlt: multiplexed over the (s,t) "
                       "strategies (Hachisuka et al. 2014)") == "pssmlt"
               ? MltSettings::Mode::Pssmlt
               : MltSettings::Mode::Mmlt;
  if (s.mode == MltSettings::Mode::Pssmlt || p.describing()) {
    p.setCondition("mode: pssmlt");
    s.base = p.getChoice("base", "path", {"path", "bdpt"},
                         "what the chains mutate: a path tracer's numbers or one BDPT sample's (all strategies)") ==
                     "path"
                 ? MltSettings::Base::Path
                 : MltSettings::Base::Bdpt;
    p.setCondition("");
  }
  s.metropolis.largeStepProbability =
      p.getFloat("large_step_probability", 0.3f,
                 {"chance that a mutation draws every number afresh (large step) instead of perturbing them",
                  Range::openClosed(0, 1)});
  s.metropolis.smallStep = mlt::SmallStep::fromSigma(
      p.getFloat("sigma", 1.f / 64, {"small step: largest perturbation s2 of a number (s1 = s2/16; Kelemen et al. 2002)",
                                     Range::open(0, 0.5)}));
  s.bootstrapSamples = uint64_t(p.getInt(
      "bootstrap_samples", 100000,
      {"independent samples estimating the normalisation b and choosing the chains' starts", Range::between(1, 1e8)}));
  s.chains = p.getInt("chains", 64, {"Markov chains (a fixed number: images do not depend on the thread count)",
                                     Range::between(1, 1 << 16)});
  if (s.mode == MltSettings::Mode::Mmlt || p.describing()) {
    p.setCondition("mode: mmlt");
    s.pilotLengths = p.getChoice("length_selection", "pilot", {"pilot", "uniform"},
                                 "how the path length is chosen: in proportion to a pilot's estimate of each length's "
                                 "contribution (mixed 9:1 with uniform), or uniformly") == "pilot";
    p.setCondition("");
  }
  bool mmlt = s.mode == MltSettings::Mode::Mmlt;
  // Read for base: bdpt and for mode: mmlt; listed under the first.
  if (mmlt || s.base == MltSettings::Base::Bdpt || p.describing()) {
    p.setCondition("base: bdpt");
    std::string mis = p.getChoice("mis", "power", {"power", "balance", "uniform"},
                                  "MIS heuristic over the (s,t) strategies (also with mode: mmlt)");
    using bidir::MisWeighting;
    s.mis = mis == "power" ? MisWeighting::Power : mis == "balance" ? MisWeighting::Balance : MisWeighting::Uniform;
    p.setCondition("");
  }
  // (mode: mmlt builds each strategy's subpaths to the chosen length, without
  // roulette: rr and rr_depth apply to pssmlt's base estimators only.)
  s.length = PathLength::read(p);
  if (mmlt && s.length.maxDepth < 1)
    p.fail("max_depth", "mode: mmlt picks a path length in [1, max_depth]: give a finite max_depth of at least 1");
  // mmlt keeps a chain and a bootstrap per length: max_depth 2^31 allocated
  // 16 GB and bootstrapped for ever (issue 34, class 5). 4096 is the longest
  // subpath the bidirectional buffers hold (SubpathBuffers::fit, bidirectional/all_strategies.h).
  if (mmlt && s.length.maxDepth > 4096)
    p.fail("max_depth", "mode: mmlt keeps a chain per path length: max_depth must be at most 4096, got " +
                            std::to_string(s.length.maxDepth));
  p.checkUnused();
  return s;
}

Mlt::Mlt(MltSettings s) : settings_(s) {}
Mlt::~Mlt() = default;

void Mlt::preprocess(const Scene& scene, const Sampler& prototype) {
  const uint64_t seed = prototype.seed();
  if (settings_.mode == MltSettings::Mode::Mmlt) {
    auto multiplexed =
        std::make_unique<mlt::MultiplexedIntegrand>(scene, settings_.length.maxSegments(), settings_.mis);
    if (settings_.pilotLengths) {
      std::vector<double> share = mlt::lengthContributions(*multiplexed, settings_.metropolis.smallStep, seed,
                                                           std::max<uint64_t>(1, settings_.bootstrapSamples / 4),
                                                           unreportedRays_);
      double total = 0;
      for (double x : share) total += x;
      std::vector<double> p(share.size());
      for (size_t k = 0; k < p.size(); ++k)
        p[k] = 0.1 / double(p.size()) + (total > 0 ? 0.9 * share[k] / total : 0.9 / double(p.size()));
      multiplexed->setLengthProbabilities(p);
    }
    integrand_ = std::move(multiplexed);
  } else if (settings_.base == MltSettings::Base::Bdpt) {
    integrand_ = std::make_unique<mlt::BdptIntegrand>(scene, settings_.length, settings_.mis);
  } else {
    PathTracerSettings path;  // the path tracer's defaults: BSDF sampling, NEE, power-heuristic MIS
    path.length = settings_.length;
    estimator_ = std::make_unique<PathEstimator>(path);
    estimator_->preprocess(scene, seed);
    integrand_ = std::make_unique<mlt::PathIntegrand>(scene, *estimator_);
  }
  Progress progress("mlt bootstrap", double(settings_.bootstrapSamples), progress_);
  bootstrap_ = mlt::runBootstrap(*integrand_, settings_.metropolis, seed, settings_.bootstrapSamples, unreportedRays_,
                                 [&](uint64_t k) { progress.advance(double(k)); });
  progress.finish();
  chains_.clear();
  if (!(bootstrap_.b > 0)) return;  // nothing reaches the camera: the image stays black
  chains_.reserve(size_t(settings_.chains));
  for (int c = 0; c < settings_.chains; ++c) {
    Pcg32 pick(hashValues(seed, 0x57a27, uint64_t(c)), 0);
    chains_.emplace_back(*integrand_, settings_.metropolis, seed, bootstrap_.choose(pick.next1D()), uint64_t(c),
                         unreportedRays_);
  }
}

void Mlt::renderPass(const Scene& scene, Film& film, const Sampler&, uint64_t pass, PassStats& stats) {
  const int W = film.width(), H = film.height();
  const uint64_t pixels = uint64_t(W) * uint64_t(H), C = chains_.size();
  film.markPassesCorrelated();
  std::vector<std::vector<Splat>> splats(C);
  std::vector<std::vector<Vec2>> nonFinite(C);
  // One mutation per pixel in all: I_j = P · b / N · Σ splats with N = P,
  // where P is the area (in pixels) the primary samples map to: the image and
  // the filter's margin around it (integrands.cpp, rasterFrom).
  const double m = scene.camera.filter().margin();
  const double scale = m == 0 ? bootstrap_.b : bootstrap_.b * (W + 2 * m) * (H + 2 * m) / double(pixels);
  tbb::parallel_for(tbb::blocked_range<uint64_t>(0, C, 1), [&](const tbb::blocked_range<uint64_t>& r) {
    uint64_t rays = 0;
    for (uint64_t c = r.begin(); c != r.end(); ++c) {
      uint64_t mutations = pixels * (c + 1) / C - pixels * c / C;
      chains_[c].run(mutations, scale, splats[c], nonFinite[c], rays);
    }
    stats.rays += rays;
  });
  stats.rays += unreportedRays_;
  unreportedRays_ = 0;
  PassImage image(W, H, &scene.camera.filter());
  for (uint64_t c = 0; c < C; ++c) {  // chain order: the same sums whatever the thread count
    for (const Splat& s : splats[c]) image.splat(s.raster, s.value, pass, film);
    for (Vec2 at : nonFinite[c]) {
      int x = std::isfinite(at.x) ? std::clamp(int(at.x), 0, W - 1) : 0;
      int y = std::isfinite(at.y) ? std::clamp(int(at.y), 0, H - 1) : 0;
      film.recordNonFinite(x, y, pass);
    }
  }
  film.addPass(image);
}

mlt::ChainStats Mlt::chainStats() const {
  mlt::ChainStats total;
  for (const auto& c : chains_) total += c.stats();
  return total;
}

std::vector<std::string> Mlt::summaryLines() const {
  char line[300];
  std::vector<std::string> lines;
  std::snprintf(line, sizeof line,
                "mlt: normalisation b = %.6g, relative standard error %.3g %% (%llu bootstrap samples, %llu non-zero, "
                "%llu non-finite and dropped)",
                bootstrap_.b, 100 * bootstrap_.relativeStandardError, (unsigned long long)bootstrap_.samples,
                (unsigned long long)bootstrap_.nonZero, (unsigned long long)bootstrap_.nonFinite);
  lines.push_back(line);
  mlt::ChainStats s = chainStats();
  auto rate = [](uint64_t a, uint64_t n) { return n > 0 ? 100.0 * double(a) / double(n) : 0.0; };
  std::snprintf(line, sizeof line, "mlt: %zu chains, acceptance %.1f %% of small steps, %.1f %% of large steps",
                chains_.size(), rate(s.smallAccepted, s.smallProposed), rate(s.largeAccepted, s.largeProposed));
  lines.push_back(line);
  return lines;
}

}  // namespace lb
