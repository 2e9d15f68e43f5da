#pragma once
// Rendering one configuration of each integrator at "fast" settings, and
// comparing integrators whose error is partly frozen into a run (a photon map,
// an irradiance cache, SPPM's photon term): their region means are averaged
// over independent seeds, with the variance of that average measured from the
// seeds' spread, and compared with Student-t critical values.
#include <memory>
#include <ostream>
#include <string>
#include <vector>
#include "core/film.h"
#include "core/scene_loader.h"
#include "integrators/render_loop.h"
#include "tests/support/render_helpers.h"

namespace lb::test {

struct IntegratorUnderTest {
  std::string name;
  std::string params;  // YAML mapping
  uint64_t spp;
};
// The six integrators with settings small enough for CI at 16×16.
const std::vector<IntegratorUnderTest>& fastIntegrators();
std::string integratorTestName(const ::testing::TestParamInfo<IntegratorUnderTest>& info);
// Printed as its name, so test names (and CTest's) do not carry raw bytes.
inline void PrintTo(const IntegratorUnderTest& it, std::ostream* os) { *os << it.name; }

// `extraParams` (a YAML mapping) is merged over the integrator's own.
Rendered renderWith(const SceneFile& scene, const IntegratorUnderTest& integrator, uint64_t seed,
                    const std::string& extraParams = "{}", uint64_t spp = 0);

// Region means averaged over `seeds` independent renders (seeds first, first+1, …).
struct SeedMeans {
  RegionMeans regions;  // mean of the per-seed means; varianceOfMean from their spread
  RunningStats imageLuminance;  // each seed's mean luminance over the whole image
  int seeds = 0;
  uint64_t nonFinite = 0;
};
SeedMeans seedMeans(const SceneFile& scene, const IntegratorUnderTest& integrator, int seeds, int regionsX,
                    int regionsY, uint64_t firstSeed, const std::string& extraParams = "{}");

// Welch t-tests, region by region and channel by channel, Šidák-corrected
// over `comparisons` at level alpha; `allowance` (relative to b) is added for
// a stated bias, and 32 ulp of float rounding. Empty when all agree, else a
// description of the failures.
std::string compareSeedMeans(const SeedMeans& a, const SeedMeans& b, double alpha, int comparisons,
                             double allowance = 0);

// Path tracing and BDPT on one scene, at its own max_depth: the region means
// of `seeds` renders of each (BDPT with a quarter of the samples), compared by
// Welch's t on the seeds' spread (compareSeedMeans, Šidák over every region
// and channel). For scenes whose samples are heavy-tailed (a glossy surface
// reflecting a small light), where one render's own variance understates the
// truth. Empty when they agree.
std::string pathBdptDisagreement(const SceneFile& scene, uint64_t pathSpp, double alpha, int seeds = 8,
                                 int regionsX = 4, int regionsY = 4);

}  // namespace lb::test
