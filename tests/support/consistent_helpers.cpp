#include "tests/support/consistent_helpers.h"
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lb::test {

std::vector<bool> noEmitterSeen(const Scene& scene) {
  return primaryHitMask(scene, [](bool hit, const SurfaceInteraction& si) { return !(hit && si.emitter); });
}

SeedMeans maskedSeedMeans(const SceneFile& sf, const RenderSpec& spec, int seeds, int regions,
                          const std::vector<bool>& mask) {
  SeedMeans out;
  out.seeds = seeds;
  std::vector<RunningStats> stats(size_t(regions * regions * 3));
  for (int s = 0; s < seeds; ++s) {
    RenderSpec one = spec;
    one.seed = spec.seed + uint64_t(s);
    Rendered r = renderWithReport(sf, one);
    out.nonFinite += r.report.nonFinite;
    RegionMeans m = regionMeans(*r.film, regions, regions, &mask);
    for (size_t i = 0; i < stats.size(); ++i) stats[i].add(m.mean[i]);
  }
  out.regions.regionsX = out.regions.regionsY = regions;
  for (const RunningStats& s : stats) {
    out.regions.mean.push_back(s.mean);
    out.regions.varianceOfMean.push_back(s.varianceOfMean());
  }
  return out;
}

Deviations deviations(const SeedMeans& a, const SeedMeans& ref) {
  Deviations d;
  for (size_t i = 0; i < a.regions.mean.size(); ++i) {
    double gap = std::abs(a.regions.mean[i] - ref.regions.mean[i]);
    if (ref.regions.mean[i] > 0) d.worst = std::max(d.worst, gap / ref.regions.mean[i]);
    d.sum += gap;
    d.noiseVar += a.regions.varianceOfMean[i] + ref.regions.varianceOfMean[i];
  }
  return d;
}

void printBiasSweep(const std::string& what, const std::vector<BiasLevel>& levels, const SeedMeans& ref) {
  for (const BiasLevel& l : levels) {
    Deviations d = deviations(l.means, ref);
    double c = 0, meanSd = 0, refSd = 0;
    for (size_t i = 0; i < ref.regions.mean.size(); ++i) {
      if (!(ref.regions.mean[i] > 0)) continue;
      double gap = std::abs(l.means.regions.mean[i] - ref.regions.mean[i]);
      c = std::max(c, gap / (ref.regions.mean[i] * l.parameter));
      refSd = std::max(refSd, std::sqrt(ref.regions.varianceOfMean[i]) / ref.regions.mean[i]);
      meanSd = std::max(meanSd, std::sqrt(l.means.regions.varianceOfMean[i] + ref.regions.varianceOfMean[i]) /
                                    ref.regions.mean[i]);
    }
    std::printf("%s, p = %g: largest deviation %.2f %% (largest noise sd %.2f %%, of which the reference's %.2f %%), "
                "summed %.4g ± %.2g, largest |d|/(ref p) %.4f\n",
                what.c_str(), l.parameter, 100 * d.worst, 100 * meanSd, 100 * refSd, d.sum, std::sqrt(d.noiseVar), c);
    std::printf("  signed relative deviations:");
    for (size_t i = 0; i < ref.regions.mean.size(); ++i)
      std::printf(" %+.2f", ref.regions.mean[i] > 0 ? 100 * (l.means.regions.mean[i] / ref.regions.mean[i] - 1) : 0.0);
    std::printf(" %%\n");
  }
  std::fflush(stdout);
}

void expectBiasWithinAndShrinking(const std::string& what, const std::vector<BiasLevel>& levels, const SeedMeans& ref,
                                  double coefficient, double alpha, int comparisons) {
  printBiasSweep(what, levels, ref);
  double z = normalCritical(alpha);
  for (size_t i = 0; i < levels.size(); ++i) {
    EXPECT_EQ(levels[i].means.nonFinite, 0u) << what << " at p = " << levels[i].parameter;
    std::string failures =
        compareSeedMeans(levels[i].means, ref, alpha, comparisons, coefficient * levels[i].parameter);
    EXPECT_TRUE(failures.empty()) << what << " at p = " << levels[i].parameter << ", allowance "
                                  << 100 * coefficient * levels[i].parameter << " %:" << failures;
    if (i == 0) continue;
    Deviations before = deviations(levels[i - 1].means, ref), now = deviations(levels[i].means, ref);
    double noise = z * std::sqrt(before.noiseVar + now.noiseVar);
    EXPECT_LT(now.sum, before.sum - noise) << what << ": the summed deviation must shrink beyond the noise from p = "
                                           << levels[i - 1].parameter << " (" << before.sum << ") to p = "
                                           << levels[i].parameter << " (" << now.sum << "), noise " << noise;
  }
}

SeedMeans scaled(SeedMeans m, double factor) {
  for (double& v : m.regions.mean) v *= factor;
  for (double& v : m.regions.varianceOfMean) v *= factor * factor;
  return m;
}

}  // namespace lb::test
