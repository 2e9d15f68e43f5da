#pragma once
// Comparing the consistent integrators (photon mapping, SPPM, the irradiance
// cache) with an unbiased reference (testing.md §5). Their error is partly
// frozen into a run (a photon map, a cache's records), so region means are
// averaged over independent seeds and their noise is measured from the
// seeds' spread; on top of it each method has a stated bias allowance,
// c × p, where p is the parameter that controls the bias (gather radius,
// photon count^(-1/2), the cache's threshold a), c is measured by a sweep
// over p, and the test also checks that the bias really shrinks with p.
#include <string>
#include <vector>
#include "tests/support/render_helpers.h"
#include "tests/support/repeats.h"

namespace lb::test {

// Pixels whose camera rays (centre and corners) hit no emitter: an emitter
// seen directly is the same for every integrator, and its edge pixels only add
// pixel-jitter noise to the comparison.
std::vector<bool> noEmitterSeen(const Scene& scene);

// Region means (regions × regions) over `seeds` independent renders (seeds
// spec.seed, spec.seed + 1, …), pixels restricted to `mask`.
SeedMeans maskedSeedMeans(const SceneFile& sf, const RenderSpec& spec, int seeds, int regions,
                          const std::vector<bool>& mask);

// Deviations of `a` from `ref` over regions and channels.
struct Deviations {
  double worst = 0;     // largest |a − ref| / ref
  double sum = 0;       // Σ |a − ref|
  double noiseVar = 0;  // Σ (var a + var ref), the seeds' variances of the means
};
Deviations deviations(const SeedMeans& a, const SeedMeans& ref);

// One point of a bias sweep: the method at parameter value p.
struct BiasLevel {
  double parameter;
  SeedMeans means;
};
// The stated allowance, checked at p[0] > p[1] > …:
//  - at each p every region agrees with `ref` (Welch t-tests on the seeds,
//    Šidák-corrected over `comparisons`) within `coefficient` × p of the
//    reference's mean (compareSeedMeans);
//  - the bias shrinks with p: the summed |deviation| at each p is smaller
//    than at the previous one by more than the noise,
//    Σ|d(p_i)| < Σ|d(p_{i−1})| − z·sqrt(V_{i−1} + V_i) (z two-sided at alpha;
//    V counts the reference's variance twice, once per level: conservative
//    when the deviations keep their sign).
// Prints the measured figures under `what`.
void expectBiasWithinAndShrinking(const std::string& what, const std::vector<BiasLevel>& levels, const SeedMeans& ref,
                                  double coefficient, double alpha, int comparisons);

// Sweeps only (no assertion): prints, per level, the largest and summed
// deviation, its noise, and the largest |d| / (ref × p) — the coefficient c
// that the allowance c × p must cover.
void printBiasSweep(const std::string& what, const std::vector<BiasLevel>& levels, const SeedMeans& ref);

// Multiplies every region mean by `factor` (deliberate breaks: a copy of the
// method's means scaled by 1.05 must fail).
SeedMeans scaled(SeedMeans m, double factor);

}  // namespace lb::test
