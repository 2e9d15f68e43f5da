#include "integrators/mlt/metropolis.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <algorithm>
#include <atomic>
#include <cmath>

namespace lb::mlt {

namespace {
bool allFinite(const std::vector<Contribution>& c) {
  for (const Contribution& x : c)
    if (!isFinite(x.value)) return false;
  return true;
}
}  // namespace

float targetValue(const std::vector<Contribution>& c) {
  float f = 0;
  for (const Contribution& x : c) f += luminance(x.value);
  return std::isfinite(f) ? std::max(f, 0.f) : 0.f;
}

float acceptance(float fCurrent, float fProposed) {
  if (!(fCurrent > 0)) return 1;
  return std::min(1.f, fProposed / fCurrent);
}

PrimarySampleVector bootstrapVector(int streams, const SmallStep& step, uint64_t seed, uint64_t index) {
  return PrimarySampleVector(streams, step, hashValues(seed, 0xb0075, index), 0);
}

uint64_t Bootstrap::choose(float u) const {
  double target = double(u) * cdf.back();
  // The first sample whose running sum exceeds the target: never one with f = 0.
  auto it = std::upper_bound(cdf.begin(), cdf.end(), target);
  return uint64_t(std::min<ptrdiff_t>(it - cdf.begin(), ptrdiff_t(cdf.size()) - 1));
}

void forEachBootstrapSample(
    const PrimarySpaceIntegrand& integrand, const SmallStep& step, uint64_t seed, uint64_t n, uint64_t& rays,
    const std::function<void(uint64_t i, PrimarySampleVector& u, const std::vector<Contribution>& c)>& record,
    const std::function<void(uint64_t)>& onProgress) {
  std::atomic<uint64_t> traced{0};
  constexpr uint64_t Block = 256;
  tbb::parallel_for(tbb::blocked_range<uint64_t>(0, (n + Block - 1) / Block), [&](const tbb::blocked_range<uint64_t>& r) {
    std::vector<Contribution> c;
    uint64_t localRays = 0;
    for (uint64_t block = r.begin(); block != r.end(); ++block) {
      uint64_t end = std::min(n, (block + 1) * Block);
      for (uint64_t i = block * Block; i < end; ++i) {
        PrimarySampleVector u = bootstrapVector(integrand.streams(), step, seed, i);
        c.clear();
        integrand.evaluate(u, c, localRays);
        record(i, u, c);
      }
      if (onProgress) onProgress(end - block * Block);
    }
    traced += localRays;
  });
  rays += traced.load();
}

Bootstrap runBootstrap(const PrimarySpaceIntegrand& integrand, const MetropolisSettings& settings, uint64_t seed,
                       uint64_t n, uint64_t& rays, const std::function<void(uint64_t)>& onProgress) {
  Bootstrap result;
  result.samples = n;
  std::vector<double> f(n, 0.0);
  std::vector<uint8_t> bad(n, 0);
  forEachBootstrapSample(
      integrand, settings.smallStep, seed, n, rays,
      [&](uint64_t i, PrimarySampleVector&, const std::vector<Contribution>& c) {
        if (!allFinite(c)) bad[i] = 1;
        else f[i] = targetValue(c);
      },
      onProgress);
  // Sums in index order: the same whatever the thread count.
  result.cdf.resize(n);
  double sum = 0, sumSq = 0;
  for (uint64_t i = 0; i < n; ++i) {
    sum += f[i], sumSq += f[i] * f[i];
    result.cdf[i] = sum;
    result.nonZero += f[i] > 0;
    result.nonFinite += bad[i];
  }
  result.b = n > 0 ? sum / double(n) : 0;
  double var = n > 1 ? std::max(0.0, (sumSq - sum * sum / double(n)) / double(n - 1)) : 0;
  result.relativeStandardError = result.b > 0 ? std::sqrt(var / double(n)) / result.b : std::nan("");
  return result;
}

ChainStats& ChainStats::operator+=(const ChainStats& o) {
  smallProposed += o.smallProposed, smallAccepted += o.smallAccepted;
  largeProposed += o.largeProposed, largeAccepted += o.largeAccepted;
  nonFinite += o.nonFinite;
  return *this;
}

MarkovChain::MarkovChain(const PrimarySpaceIntegrand& integrand, const MetropolisSettings& settings, uint64_t seed,
                         uint64_t start, uint64_t chain, uint64_t& rays)
    : integrand_(integrand),
      settings_(settings),
      u_(bootstrapVector(integrand.streams(), settings.smallStep, seed, start)),
      decisions_(hashValues(seed, 0xc4a1, chain), 1) {
  integrand_.evaluate(u_, current_, rays);
  fCurrent_ = allFinite(current_) ? targetValue(current_) : 0.f;
  u_.reseed(hashValues(seed, 0x3a7e, chain), 2);
}

void MarkovChain::splatCurrent(double scale, std::vector<Splat>& splats) {
  if (weight_ > 0 && fCurrent_ > 0) {
    double w = weight_ * scale / double(fCurrent_);  // in double: f may be tiny
    for (const Contribution& c : current_) splats.push_back({c.raster, Color(glm::dvec3(c.value) * w)});
  }
  weight_ = 0;
}

void MarkovChain::run(uint64_t mutations, double scale, std::vector<Splat>& splats, std::vector<Vec2>& nonFinite,
                      uint64_t& rays) {
  for (uint64_t m = 0; m < mutations; ++m) {
    bool large = decisions_.next1D() < settings_.largeStepProbability;
    u_.startIteration(large);
    proposed_.clear();
    integrand_.evaluate(u_, proposed_, rays);
    float fProposed = 0;
    if (allFinite(proposed_)) {
      fProposed = targetValue(proposed_);
    } else {
      for (const Contribution& c : proposed_)
        if (!isFinite(c.value)) nonFinite.push_back(c.raster);
      ++stats_.nonFinite;
    }
    float a = acceptance(fCurrent_, fProposed);
    (large ? stats_.largeProposed : stats_.smallProposed)++;
    // Expected values: the proposal gets a, the current state 1 − a.
    weight_ += 1 - double(a);
    if (a > 0 && fProposed > 0) {
      double w = double(a) * scale / double(fProposed);
      for (const Contribution& c : proposed_) splats.push_back({c.raster, Color(glm::dvec3(c.value) * w)});
    }
    if (decisions_.next1D() < a) {
      splatCurrent(scale, splats);
      std::swap(current_, proposed_);
      fCurrent_ = fProposed;
      u_.accept();
      (large ? stats_.largeAccepted : stats_.smallAccepted)++;
    } else {
      u_.reject();
    }
  }
  splatCurrent(scale, splats);
}

}  // namespace lb::mlt
