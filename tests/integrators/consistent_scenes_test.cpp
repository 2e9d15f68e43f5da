// The consistent integrators against BDPT where consistent_caustic_test.cpp
// does not reach (issue 11, "agreement beyond the Cornell box"): the
// irradiance cache on every caustic scene and on the Cornell box with
// spheres, and all three on the water pool (its caustic seen through the
// water, L S D S E) and on Veach's MIS scene (glossy plates, no delta
// surface). Each within c × p of BDPT (consistent_cases.h), c from the sweeps
// below (DISABLED_ tests; signed deviation of the region means from BDPT's,
// ± the noise sd, the largest over regions where the scene has a grid), and
// the bias shown to shrink where a sweep resolves it.
//
//   cache, glass sphere (base photon, N0 1e6, 64 stratified samples, 8
//     seeds): +5.10 ± 0.7 %, +2.44 ± 1.0 %, +1.58 ± 0.9 %, +0.21 ± 0.7 %;
//     |d|/(ref p) 0.026, 0.024, 0.032, 0.008 → c = 0.035, tested at p = 2,
//     0.5. The caustic map's k-nearest excess, as for photon mapping
//     (consistent_caustic_test.cpp): the cache takes caustics from it.
//   cache, metal ring (N0 1e5): −2.41 ± 0.5 %, −2.02 ± 0.4 %, −0.63 ± 0.3 %,
//     −0.61 ± 0.2 %; |d|/(ref p) 0.012, 0.020, 0.013, 0.024 → c = 0.025,
//     tested at p = 2, 0.5.
//   cache, enclosed light: +0.59, −0.61, −0.70, −0.41 % (noise sd 0.3–0.5 %);
//     up to 0.017 at p = 0.25 → c = 0.02 at p = 1 only: not resolved.
//   cache, Cornell box with spheres (3 × 3 regions, 24 × 24): base photon
//     6.1, 4.3, 5.8, 4.8 % (noise sd 5–6 %; |d|/(ref p) 0.031, 0.043 at p =
//     2, 1), base path (16 seeds) 4.6, 4.1, 8.3, 4.1 % (noise sd 4–5 %;
//     0.023, 0.041) → c = 0.045 at p = 1 only: records that see the light
//     through the glass sphere by chance freeze their noise into blotches
//     (sd of a region over seeds: several %), which hides the bias. These
//     tests catch light counted twice or lost (tens of %), not 5 %.
//   water pool (the variant below; 3 × 3 regions, BDPT 8 × 1024 spp, noise
//     sd 1.2 %; N0 1.6e6 caustic photons, G0 1e5 global):
//     photon 17.2, 7.0, 5.1 % (p = 2, 1, 0.5; noise sd 3.4–4.3 %;
//       |d|/(ref p) 0.086, 0.070, 0.102); at N0 1e5 it read −34, −30, −14,
//       −5 % for p = 2 … 0.25: so few photons reach the pool that r_k is a
//       fair fraction of it, and the boundary bias dominates → c = 0.1 at
//       p = 1.
//     cache 13.1, 7.1, 4.3 % (|d|/(ref p) 0.065, 0.071, 0.085) → c = 0.09
//       at p = 1.
//     sppm (R0 0.05) 11.6, 5.1, 10.0, 12.3 % (p = 2 … 0.25; noise sd 4, 5,
//       7, 14 %: at 24 passes its noise grows faster than its bias falls);
//       |d|/(ref p) 0.058 and 0.051 at p = 2, 1 → c = 0.06 at p = 1.
//     Not resolved below p = 1 by any of the three: these catch a missing
//     or doubled term (tens of %), not 5 %.
//   Veach's MIS scene (3 × 3 regions, 4 × 4 stratified samples):
//     cache 4.2, 1.4, 4.5, 2.6 % (noise sd 3–4.5 %), photon 4.2, 1.2, 2.1,
//     3.1 % (noise sd 2.2–3.5 %); |d|/(ref p) at p = 2, 1 at most 0.021 →
//     c = 0.025 at p = 1 only.
//     SPPM is left out here: its visible points on the near-mirror plates
//     (roughness 0.005) gather photons for a reflection of a tiny light, and
//     a region's mean over 8 seeds has sd 40–57 % there (deviations up to
//     45 %, within that noise): the sweep resolves nothing. Gathering at
//     near-specular glossy vertices is SPPM's known weakness (the README).
//   Bitterli's Cornell box imported from Mitsuba XML (issue 14; 3 × 3
//     regions at 24 × 24, BDPT 8 × 256 spp, noise sd of the reference 0.28 %):
//     sppm (R0 0.05 p) summed |d| 0.044, 0.023, 0.015, 0.015 for p = 2, 1,
//       0.5, 0.25 (± 0.0015 … 0.0039), every region below BDPT (the
//       radius's boundary bias in the corners); largest |d|/(ref p) 0.030,
//       0.029, 0.032 at p = 2 … 0.5 → c = 0.035, tested at p = 2 and 0.5:
//       the bias shrinks with the radius until p = 0.5, below which 24
//       passes' noise (sd 2.2 %) hides it.
//     photon 3.1, 5.1, 2.0, 3.4 % (noise sd 2.3–3.6 %): not resolved;
//       |d|/(ref p) 0.015, 0.051 at p = 2, 1 → c = 0.055 at p = 1 only.
//   The glossy sphere under the sky map (env-glossy, 3 × 3 regions at
//     64 × 40, BDPT 8 × 256 spp, reference noise sd 0.8 %): photon 8.1,
//     1.4, 1.9, 4.6 % for p = 2 … 0.25 (noise sd 3.6–5.5 %), sppm 2.8,
//     2.6, 3.7, 5.1 % (noise sd 1.8–5.4 %): neither resolved above its noise;
//     |d|/(ref p) at p = 2, 1: photon 0.040, 0.014 → c = 0.045; sppm 0.014,
//     0.026 → c = 0.03, both at p = 1 only. They catch environment light lost
//     or doubled by the photon paths (tens of %), not 5 %: means × 1.15
//     (photon) and × 1.10 (sppm) fail them, checked once.
//   The other imported Bitterli scenes (3 × 3 regions; p = 2, 1, 0.5):
//     veach-mis (80 × 45, as VeachMis above): photon 2.8, 2.0, 2.8 % (noise
//       sd 2.3–3.3 %, the reference's 1.1 %); |d|/(ref p) 0.014, 0.020 at
//       p = 2, 1 → c = 0.025 at p = 1 only, as on the YAML scene.
//     veach-bidir (24 × 24, BDPT 8 × 2048 spp, reference noise sd 4.0 %):
//       photon 16.0, 16.9, 13.1 % (noise sd 11–15 %), sppm 4.0, 5.7, 15.3 %
//       (noise sd 4.9–7.6 %); |d|/(ref p) at p = 2, 1: photon 0.080, 0.169
//       → c = 0.17; sppm 0.020, 0.057 → c = 0.06; both at p = 1 only. The
//       glass's caustic is heavy-tailed in every estimator here: these
//       catch light lost or doubled, nothing finer.
//     water-caustic with the larger light (32 × 32, BDPT 8 × 1024 spp):
//       the reference's own noise sd is 12.3 % per region; photon 23, 12,
//       11 % (noise sd 24–34 %; its sweep took 7.6 min), sppm 19, 14, 14 %.
//       Nothing resolvable at a CI budget: sweeps only (DISABLED_), no test.
//
// Deliberate break, checked once by hand (expectConsistentScaled, means ×
// 1.05): cache, glass sphere: p = 0.5 gap 0.0452 > 0.0341 and p = 2 gap
// 0.0863 > 0.0739 (with 8 seeds instead of 16 it passed: hence 16);
// cache, metal ring: p = 0.5 gap 0.0319 > 0.0236, and the deviation grows
// from p = 2 (0.064) to 0.5 (0.094); cache, enclosed light: p = 1 gap 0.0420
// > 0.0397; photon, Veach's scene: region 8 gap 0.00091 > 0.00086; sppm,
// Bitterli's Cornell box: p = 0.5, region 4 gap 0.0094 > 0.0072 (and five
// more). The Cornell and pool cases, and photon mapping on Bitterli's box,
// do not catch 5 % (see above).
#include <gtest/gtest.h>
#include <string>
#include "tests/support/consistent_cases.h"

namespace lb::test {
namespace {

constexpr double Alpha = 1e-3;

std::string count(double n) { return std::to_string(long(n)); }

// The cache with photon-map records (base: photon): the caustic map at the
// cached point, the global map after a record ray's first bounce. p scales
// every bias parameter: photon counts N0/p², G0/p² (k-NN radii ∝ p) and
// Ward's a.
const ConsistentMethod CacheMethod{"irradiance_cache",
                                   [](double p, const Scale& s) {
                                     return "{base: photon, caustic_photons: " + count(s.photons / (p * p)) +
                                            ", global_photons: " + count(s.globalPhotons / (p * p)) +
                                            ", a: " + std::to_string(0.15 * p) + ", record_image: false}";
                                   },
                                   4};
// Photon mapping with both maps scaled (on Veach's scene the caustic map is
// empty and the global map carries the bias).
const ConsistentMethod PhotonMethod{"photon",
                                    [](double p, const Scale& s) {
                                      return "{caustic_photons: " + count(s.photons / (p * p)) +
                                             ", global_photons: " + count(s.globalPhotons / (p * p)) +
                                             ", final_gather: 2, k: 30}";
                                    },
                                    4};

// The shipped pool's sun is a sphere of radius 0.25 six units away: seen
// through the water (L S D S E) only a camera path refracted onto it finds
// it, so BDPT's reference there stays noisy (region sd 31 % at 8 × 128 spp;
// references good enough for the shipped pool are issue 13's). This variant
// has the same pool and water under a sun of radius 1.5 with the same power
// (900 × (0.25/1.5)² = 25): the same paths, found often enough to converge.
const ConsistentScene WaterPool{"water-pool", 64, 48, 1024, 0, 8, {0.05, 1.6e6, 1e5}, 3,
                                "shapes:\n"
                                "  - {type: box, material: tiles, transform: {scale: [0.82, 0.05, 0.82], translate: [0, -0.65, 0]}}\n"
                                "  - {type: mesh, file: meshes/water.obj, material: water, smooth_normals: true}\n"
                                "  - {type: sphere, material: none, center: [1.5, 6, -2], radius: 1.5, emission: 25}\n"
                                "  - {type: sphere, material: none, center: [0, 8, 4], radius: 2, emission: 0.3}\n"
                                "sampler: {type: stratified, strata: 4}\n"};
// Tiny bright lights reflected in near-mirror plates: sub-pixel highlights,
// so camera samples are stratified (as for the glass sphere's caustic).
const ConsistentScene VeachMis{"veach-mis", 80, 50, 128, 0, 8, {0.1, 1e5, 1e5}, 3,
                               "sampler: {type: stratified, strata: 4}\n"};
const ConsistentScene CornellSpheres{"cornell-box-spheres", 24, 24, 256, 0, 8, {0.1, 1e5, 1e5}, 3};
// Bitterli's Cornell box as imported from its Mitsuba XML (issue 14): all
// diffuse, the photon methods' home ground.
// A glossy copper sphere on a diffuse floor under the HDR sky map (issue 14:
// the photon methods must emit from the map too, and gather its light off
// the glossy sphere).
const ConsistentScene EnvGlossy{"env-glossy", 64, 40, 256, 0, 8, {0.05, 1e5, 1e5}, 3};
// The other imported scenes: veach-mis as the YAML VeachMis above, veach-bidir
// (its indirect light and the glass's caustic), and water-caustic with a
// larger light at the same power (tests/data/water-caustic-larger-light.yaml,
// the importer's translation: the shipped light leaves every reference noisy).
const ConsistentScene BitterliVeachMis{"external/veach-mis/scene.xml", 80, 45, 128, 0, 8, {0.1, 1e5, 1e5}, 3,
                                       "sampler: {type: stratified, strata: 4}\n"};
const ConsistentScene BitterliVeachBidir{"external/veach-bidir/scene.xml", 24, 24, 2048, 0, 8, {0.05, 1e5, 1e5}, 3};
const ConsistentScene WaterCausticLarger{"../tests/data/water-caustic-larger-light", 32, 32, 1024, 0, 8, {0.05, 1.6e6, 1e5}, 3};
const ConsistentScene BitterliCornell{"external/cornell-box/scene.xml", 24, 24, 256, 0, 8, {0.05, 1e5, 1e5}, 3};

// The cache over the path tracer (base: path): p scales Ward's a only.
const ConsistentMethod PathCacheMethod{"irradiance_cache",
                                       [](double p, const Scale&) {
                                         return "{a: " + std::to_string(0.15 * p) + ", record_image: false}";
                                       },
                                       4};
const ConsistentMethod StratifiedCacheMethod{CacheMethod.integrator, CacheMethod.params, 64, Stratified};

// 16 samples per pixel: one block of the pool's and Veach's 4 × 4 strata.
const ConsistentMethod Cache16{CacheMethod.integrator, CacheMethod.params, 16},
    Photon16{PhotonMethod.integrator, PhotonMethod.params, 16};

const ConsistentCase CacheGlass{GlassSphere, StratifiedCacheMethod, 16}, CacheRing{MetalRing, CacheMethod, 8},
    CacheEnclosed{EnclosedLight, CacheMethod, 8}, CachePool{WaterPool, Cache16, 8},
    PhotonPool{WaterPool, Photon16, 8}, SppmPool{WaterPool, SppmMethod, 8}, CacheVeach{VeachMis, Cache16, 8},
    PhotonVeach{VeachMis, Photon16, 8}, SppmVeach{VeachMis, SppmMethod, 8},
    CacheCornell{CornellSpheres, CacheMethod, 8}, PathCacheCornell{CornellSpheres, PathCacheMethod, 16},
    PhotonBitterli{BitterliCornell, PhotonMethod, 8}, SppmBitterli{BitterliCornell, SppmMethod, 8},
    PhotonEnv{EnvGlossy, PhotonMethod, 8}, SppmEnv{EnvGlossy, SppmMethod, 8},
    PhotonBitterliMis{BitterliVeachMis, Photon16, 8}, PhotonBitterliBidir{BitterliVeachBidir, PhotonMethod, 8},
    SppmBitterliBidir{BitterliVeachBidir, SppmMethod, 8}, PhotonWater{WaterCausticLarger, PhotonMethod, 8},
    SppmWater{WaterCausticLarger, SppmMethod, 8};

// c from the sweeps (top of the file), rounded up; levels as there.
// Disabled for CI's length (it took 44 s of 2 cores, the suite's longest
// case): the cache's caustics are the caustic map's k-nearest estimate,
// which PhotonOnTheGlassSphere tests on this scene, and the cache's use of
// them is held to 5 % on the metal ring and through the enclosed light's
// glass below. Run it by hand after a change to how the cache takes caustics:
//   ./build/tests/integrator_tests --gtest_also_run_disabled_tests
//     --gtest_filter=ConsistentScenes.DISABLED_CacheOnTheGlassSphere   (one command line)
TEST(ConsistentScenes, DISABLED_CacheOnTheGlassSphere) { expectConsistent(CacheGlass, {2, 0.5}, 0.035, Alpha); }
TEST(ConsistentScenes, CacheOnTheMetalRing) { expectConsistent(CacheRing, {2, 0.5}, 0.025, Alpha); }
// Not resolved above the noise at any p swept: the allowance only.
TEST(ConsistentScenes, CacheOnTheEnclosedLight) { expectConsistent(CacheEnclosed, {1}, 0.02, Alpha); }
TEST(ConsistentScenes, CacheOnTheCornellBoxWithSpheres) { expectConsistent(CacheCornell, {1}, 0.045, Alpha); }
TEST(ConsistentScenes, PathCacheOnTheCornellBoxWithSpheres) {
  expectConsistent(PathCacheCornell, {1}, 0.045, Alpha);
}
TEST(ConsistentScenes, PhotonOnTheWaterPool) { expectConsistent(PhotonPool, {1}, 0.1, Alpha); }
TEST(ConsistentScenes, CacheOnTheWaterPool) { expectConsistent(CachePool, {1}, 0.09, Alpha); }
TEST(ConsistentScenes, SppmOnTheWaterPool) { expectConsistent(SppmPool, {1}, 0.06, Alpha); }
TEST(ConsistentScenes, CacheOnVeachsScene) { expectConsistent(CacheVeach, {1}, 0.025, Alpha); }
TEST(ConsistentScenes, PhotonOnVeachsScene) { expectConsistent(PhotonVeach, {1}, 0.025, Alpha); }

TEST(ConsistentScenes, SppmOnBitterlisCornellBox) { expectConsistent(SppmBitterli, {2, 0.5}, 0.035, Alpha); }
TEST(ConsistentScenes, PhotonOnBitterlisCornellBox) { expectConsistent(PhotonBitterli, {1}, 0.055, Alpha); }
TEST(ConsistentScenes, PhotonUnderTheSkyMap) { expectConsistent(PhotonEnv, {1}, 0.045, Alpha); }
TEST(ConsistentScenes, SppmUnderTheSkyMap) { expectConsistent(SppmEnv, {1}, 0.03, Alpha); }
TEST(ConsistentScenes, PhotonOnBitterlisVeachMis) { expectConsistent(PhotonBitterliMis, {1}, 0.025, Alpha); }
TEST(ConsistentScenes, PhotonOnBitterlisVeachBidir) { expectConsistent(PhotonBitterliBidir, {1}, 0.17, Alpha); }
TEST(ConsistentScenes, SppmOnBitterlisVeachBidir) { expectConsistent(SppmBitterliBidir, {1}, 0.06, Alpha); }
TEST(ConsistentScenes, DISABLED_PhotonBitterliVeachMisBiasSweep) { printSweep(PhotonBitterliMis, {2, 1, 0.5}); }
TEST(ConsistentScenes, DISABLED_PhotonBitterliVeachBidirBiasSweep) { printSweep(PhotonBitterliBidir, {2, 1, 0.5}); }
TEST(ConsistentScenes, DISABLED_SppmBitterliVeachBidirBiasSweep) { printSweep(SppmBitterliBidir, {2, 1, 0.5}); }
TEST(ConsistentScenes, DISABLED_PhotonWaterCausticBiasSweep) { printSweep(PhotonWater, {2, 1, 0.5}); }
TEST(ConsistentScenes, DISABLED_SppmWaterCausticBiasSweep) { printSweep(SppmWater, {2, 1, 0.5}); }
TEST(ConsistentScenes, DISABLED_PhotonEnvGlossyBiasSweep) { printSweep(PhotonEnv); }
TEST(ConsistentScenes, DISABLED_SppmEnvGlossyBiasSweep) { printSweep(SppmEnv); }
TEST(ConsistentScenes, DISABLED_PhotonBitterliCornellBiasSweep) { printSweep(PhotonBitterli); }
TEST(ConsistentScenes, DISABLED_SppmBitterliCornellBiasSweep) { printSweep(SppmBitterli); }
TEST(ConsistentScenes, DISABLED_CacheGlassSphereBiasSweep) { printSweep(CacheGlass); }
TEST(ConsistentScenes, DISABLED_CacheMetalRingBiasSweep) { printSweep(CacheRing); }
TEST(ConsistentScenes, DISABLED_CacheEnclosedLightBiasSweep) { printSweep(CacheEnclosed); }
TEST(ConsistentScenes, DISABLED_CacheWaterPoolBiasSweep) { printSweep(CachePool, {2, 1, 0.5}); }
TEST(ConsistentScenes, DISABLED_PhotonWaterPoolBiasSweep) { printSweep(PhotonPool, {2, 1, 0.5}); }
TEST(ConsistentScenes, DISABLED_SppmWaterPoolBiasSweep) { printSweep(SppmPool); }
TEST(ConsistentScenes, DISABLED_CacheVeachMisBiasSweep) { printSweep(CacheVeach); }
TEST(ConsistentScenes, DISABLED_PhotonVeachMisBiasSweep) { printSweep(PhotonVeach); }
TEST(ConsistentScenes, DISABLED_SppmVeachMisBiasSweep) { printSweep(SppmVeach); }
TEST(ConsistentScenes, DISABLED_CacheCornellSpheresBiasSweep) { printSweep(CacheCornell); }
TEST(ConsistentScenes, DISABLED_PathCacheCornellSpheresBiasSweep) { printSweep(PathCacheCornell); }

}  // namespace
}  // namespace lb::test
