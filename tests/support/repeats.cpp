#include "tests/support/repeats.h"
#include <algorithm>
#include <sstream>
#include <yaml-cpp/yaml.h>

namespace lb::test {

const std::vector<IntegratorUnderTest>& fastIntegrators() {
  static const std::vector<IntegratorUnderTest> list = {
      {"path", "{}", 16},
      {"light", "{}", 16},
      {"bdpt", "{}", 8},
      {"photon", "{global_photons: 20000, caustic_photons: 20000, final_gather: 4}", 4},
      {"sppm", "{photons_per_pass: 10000}", 8},
      {"irradiance_cache", "{theta_strata: 8, phi_strata: 24, record_image: false}", 8},
  };
  return list;
}

std::string integratorTestName(const ::testing::TestParamInfo<IntegratorUnderTest>& info) { return info.param.name; }

Rendered renderWith(const SceneFile& sf, const IntegratorUnderTest& it, uint64_t seed, const std::string& extra,
                    uint64_t spp) {
  YAML::Node params = YAML::Load(it.params);
  YAML::Node more = YAML::Load(extra);
  for (auto kv = more.begin(); kv != more.end(); ++kv) params[kv->first.as<std::string>()] = kv->second;
  YAML::Emitter merged;
  merged << YAML::Flow << params;
  return renderWithReport(sf, {it.name, merged.c_str(), spp ? spp : it.spp, seed});
}

SeedMeans seedMeans(const SceneFile& sf, const IntegratorUnderTest& it, int seeds, int rx, int ry, uint64_t first,
                    const std::string& extra) {
  SeedMeans out;
  out.seeds = seeds;
  std::vector<RunningStats> stats(size_t(rx * ry * 3));
  for (int s = 0; s < seeds; ++s) {
    Rendered r = renderWith(sf, it, first + uint64_t(s), extra);
    out.nonFinite += r.report.nonFinite;
    RegionMeans m = regionMeans(*r.film, rx, ry);
    Image image = r.film->image();
    double sum = 0;
    for (const Color& c : image.pixels) sum += double(luminance(c));
    out.imageLuminance.add(sum / double(image.pixels.size()));
    for (size_t i = 0; i < stats.size(); ++i) stats[i].add(m.mean[i]);
  }
  out.regions.regionsX = rx, out.regions.regionsY = ry;
  for (const RunningStats& s : stats) {
    out.regions.mean.push_back(s.mean);
    out.regions.varianceOfMean.push_back(s.varianceOfMean());
  }
  return out;
}

std::string compareSeedMeans(const SeedMeans& a, const SeedMeans& b, double alpha, int comparisons, double allowance) {
  double level = sidak(alpha, comparisons);
  std::ostringstream failures;
  for (size_t i = 0; i < a.regions.mean.size(); ++i) {
    double va = a.regions.varianceOfMean[i], vb = b.regions.varianceOfMean[i];
    // Welch–Satterthwaite degrees of freedom.
    double dof = (va + vb) * (va + vb) / (va * va / std::max(a.seeds - 1, 1) + vb * vb / std::max(b.seeds - 1, 1));
    if (!(dof >= 1)) dof = std::max(1, std::min(a.seeds, b.seeds) - 1);
    double gap = std::abs(a.regions.mean[i] - b.regions.mean[i]);
    // Plus float rounding (32 ulp, as in meanMatches) for zero-variance estimators.
    double rounding = 32 * double(MachineEpsilon) * std::max(std::abs(a.regions.mean[i]), std::abs(b.regions.mean[i]));
    double bound = studentCritical(level, dof) * std::sqrt(va + vb) + allowance * std::abs(b.regions.mean[i]) + rounding;
    if (!(gap <= bound))
      failures << " region " << i / 3 << " channel " << i % 3 << ": " << a.regions.mean[i] << " vs " << b.regions.mean[i]
               << " (gap " << gap << " > " << bound << ");";
  }
  return failures.str();
}

std::string pathBdptDisagreement(const SceneFile& sf, uint64_t pathSpp, double alpha, int seeds, int rx, int ry) {
  std::string params = "{max_depth: " + sf.integrator["max_depth"].as<std::string>() + "}";
  SeedMeans path = seedMeans(sf, {"path", params, pathSpp / uint64_t(seeds)}, seeds, rx, ry, 3);
  SeedMeans bdpt = seedMeans(sf, {"bdpt", params, std::max<uint64_t>(1, pathSpp / 4 / uint64_t(seeds))}, seeds, rx, ry, 1003);
  return compareSeedMeans(path, bdpt, alpha, rx * ry * 3);
}

}  // namespace lb::test
