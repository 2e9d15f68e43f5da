// The consistent integrators (SPPM, photon mapping) against BDPT on the
// shipped caustic scenes (issue 11, "agreement beyond the Cornell box";
// caustic_agreement_test.cpp compares the unbiased ones). The region compared
// is the caustic itself: the diffuse pixels at least 3× the median diffuse
// pixel, chosen on an independent light-tracing image (as in
// caustic_agreement_test.cpp). Both sides are means over seeds (the
// consistent side's spread includes the noise frozen into its photon maps);
// each method runs at two levels of its bias parameter p, within a stated
// allowance c × p beyond the seeds' t-bound, and its deviation at the smaller
// p must be smaller beyond the noise (consistent_helpers.h); where the bias is
// not resolved above the noise, at one level and the allowance only.
// Settings: SPPM 24 passes × 20000 photons; photon mapping k = 30,
// global_photons 50000, final_gather 2, 4 spp (on the glass sphere: see
// StratifiedPhotonMethod); seeds per case below.
//
// The bias on a caustic is the proximity bias: its sharp edges are spread
// over the gather disc into the dark surround, so the caustic region loses
// light across its border, first order in the radius.
//   sppm    initial_radius R0 p, alpha 0.99 (the radius stays almost fixed)
//   photon  caustic_photons N0 / p², k-nearest radius (k = 30): r_k ∝ N^(-1/2) ∝ p
//
// Sweeps (DISABLED_ tests below, p = 2, 1, 0.5, 0.25; signed deviation of
// the caustic region's mean from BDPT's ± the noise sd, and the largest
// |d| / (ref p); two independent runs where two figures are given):
//   sppm, glass sphere (R0 0.05, 24 passes × 20000 photons, 6 seeds):
//     −23.7 ± 0.9 %, −4.8 ± 1.0 %, +3.7 ± 1.8 %, −3.3 ± 2.5 %;
//     |d|/(ref p) 0.119, 0.048, 0.074, 0.131 (a 64-pass × 8-seed run:
//     0.121, 0.046, 0.027, 0.028) → c = 0.14. Resolved and shrinking only
//     from p = 2 to 1; below p = 1 the deviation is within the noise. At
//     p = 2 the radius (0.1) is comparable with the caustic, so the bias is
//     above linear there: c is set by p = 2 and is loose at p = 1, which is
//     why a 5 % scale of the SPPM means does not fail this test (below).
//   sppm, metal ring (R0 0.2, 8 seeds): −3.70 ± 0.24 %, −1.78 / −1.97 ± 0.2 %,
//     −1.40 / −0.86 ± 0.2 %, −0.82 ± 0.22 %; |d|/(ref p) 0.019, 0.018 / 0.020,
//     0.028 / 0.017, 0.033 → c = 0.035. Tested at p = 2, 1: from 1 to 0.5
//     one run of two did not shrink beyond the noise.
//   photon, metal ring (N0 1e5, 24 seeds): −2.05 ± 0.38 %, −1.14 / −1.52 ± 0.23 %,
//     −0.68 / −0.58 ± 0.2 %, −0.26 ± 0.17 %; |d|/(ref p) 0.010, 0.011 / 0.015,
//     0.014 / 0.012, 0.010 (an 8-seed run: up to 0.0153) → c = 0.02. Tested
//     at p = 2, 0.5: from 1 to 0.5 one run of two did not shrink beyond the
//     noise.
//   photon, glass sphere (k = 30, N0 1e6, 8 seeds, 64 stratified camera
//     samples, global_photons 1e5, final_gather 1): +5.93 ± 1.3 %,
//     +2.47 ± 1.2 %, −0.07 ± 0.8 %, +0.46 ± 0.8 %; |d|/(ref p) 0.030, 0.025,
//     0.002, 0.019 (the test's run, 16 seeds against 24 of BDPT: +5.56 ± 0.9 %
//     at p = 2, +1.96 ± 0.7 % at p = 0.5, 0.028 and 0.039) → c = 0.045.
//     Tested at p = 2, 0.5. The k-nearest estimate
//     over-counts here: the caustic is sharper than the disc, and at a dark
//     point near it r_k reaches into the bright core, so the estimate's
//     1/r_k² tail adds light that a fixed disc would not (a fixed disc's
//     estimate integrates over the surface to exactly the flux that landed).
//     The excess shrinks as r_k does, ∝ N^(-1/2) ∝ p (paired runs at 2.5e5,
//     1e6, 4e6 photons with 16 seeds: +7 %, +3.7 %, +1 % against LT).
//     An earlier sweep (4 independent camera samples per pixel, N0 1e5) read
//     +6 … +19 % at every p, never shrinking: the caustic's core is finer
//     than a pixel, so few camera samples per pixel give heavy-tailed
//     seed means whose spread understated the noise. With 4 samples the
//     9-pixel mean's sd per seed is ~15 %; with 64 stratified ones ~1 %.
//   photon with a fixed disc (k: 0, max_radius R0 p = 0.05 p, 1e6 caustic
//     photons, as above): −14.85 %, −2.01 %, −0.96 %, −0.03 % (± 0.8–0.9 %):
//     the proximity bias, negative as for SPPM; not tested beyond the sweep
//     (SPPM tests the fixed disc).
//   sppm, enclosed light (R0 0.2, 8 seeds; the test uses 3): −3.83 ± 0.15 %,
//     −1.01 ± 0.16 %, −0.46 ± 0.14 %, −0.23 ± 0.15 %; |d|/(ref p) 0.019,
//     0.010, 0.009, 0.009 (test runs at 3–4 seeds: 0.0198 / 0.0189 at p = 2)
//     → c = 0.025. Tested at p = 2, 1.
//   photon, enclosed light (N0 1e5, 16 seeds; the test uses 8): +0.05 ± 0.37 %,
//     +0.18 ± 0.29 %, −0.41 ± 0.31 %, −0.42 ± 0.27 %; |d|/(ref p) up to
//     0.017 (at p = 0.25) → c = 0.02. Not resolved above the noise at any p:
//     the test checks the allowance at p = 1 only, no shrink.
//
// On the metal ring the pixels the 3× median rule selects (778 of 3072 at
// 64 × 48) are mostly the table's direct highlight around the cardioid, as
// caustic_agreement_test.cpp notes; the bias measured there is the methods'
// bias on that whole region.
//
// Deliberate break, checked once by hand (expectConsistentScaled): the method's means × 1.05
// fail
//   sppm, metal ring: p = 1 gap 0.0277 > 0.0258 (+4.3 %), and the deviation
//     grows from p = 2 (0.043) to p = 1 (0.076);
//   photon, metal ring: p = 0.5 gap 0.033 > 0.015 (+4.8 %), and the deviation
//     grows from p = 2 (0.070) to p = 0.5 (0.097);
//   sppm, enclosed light: p = 1 gap 0.0298 > 0.0288 (+3.8 %), and the
//     deviation grows from p = 2 (0.025) to p = 1 (0.089);
//   photon, enclosed light: p = 1 gap 0.041 > 0.036 (+5.1 %).
//   photon, glass sphere: p = 0.5 gap 0.0556 > 0.0435 (+7.06 %).
// They do NOT fail SPPM on the glass sphere: its bias is −24 % at p = 2 and
// −4.8 % at p = 1, so × 1.05 gives −20 % and 0.0 %, within the allowance
// and still shrinking. Catching a 5 % error there needs p ≤ 0.5 resolved,
// about 4× the passes this test can afford in 8 s.
#include <gtest/gtest.h>
#include <string>
#include "tests/support/consistent_cases.h"

namespace lb::test {
namespace {

constexpr double Alpha = 1e-3;

const ConsistentMethod PhotonMethod{"photon",
                                    [](double p, const Scale& s) {
                                      return "{caustic_photons: " + std::to_string(int(s.photons / (p * p))) +
                                             ", global_photons: 50000, final_gather: 2, k: 30}";
                                    },
                                    4};
// On the glass sphere the caustic has structure finer than a pixel, so a
// pixel's value also needs many well-spread camera samples: with 4
// independent ones per pixel the seeds' means there are heavy-tailed and
// their spread understates the noise. Stratified 8 × 8 camera samples make
// that noise small beside the photon map's.
const ConsistentMethod StratifiedPhotonMethod{"photon",
                                              [](double p, const Scale& s) {
                                                return "{caustic_photons: " + std::to_string(int(s.photons / (p * p))) +
                                                       ", global_photons: 100000, final_gather: 1, k: 30}";
                                              },
                                              64, Stratified};
// Photon mapping with a fixed disc (k: 0, every photon within max_radius =
// R0 p): the estimate at a point is the flux in the disc over its area,
// which integrates over the surface to the flux that landed (no excess).
const ConsistentMethod FixedRadiusPhotonMethod{"photon",
                                               [](double p, const Scale& s) {
                                                 return "{caustic_photons: " + std::to_string(int(s.photons)) +
                                                        ", global_photons: 100000, final_gather: 1, k: 0, max_radius: " +
                                                        std::to_string(s.radius * p) + "}";
                                               },
                                               64, Stratified};

// Bidirectional photon mapping (vcm's bpm mode: merging at every camera
// vertex, no connections) with a fixed radius R0 p (alpha 1), with
// stratified camera samples as above.
const ConsistentMethod BpmMethod{"vcm",
                                 [](double p, const Scale& s) {
                                   return "{mode: bpm, alpha: 1, radius: " + std::to_string(s.radius * p) + "}";
                                 },
                                 64, Stratified};

// The path tracer with path-space regularization (regularize: true,
// core/bsdfs/regularization.h) at a fixed roughness
// α = 0.2 p (regularize_exponent 0): the delta vertices after the floor (the
// sphere's two surfaces on the way to the light) scatter by GGX glass of
// roughness α, so the caustic is the one a slightly rough sphere casts.
const ConsistentMethod RegularizedPathMethod{"path",
                                             [](double p, const Scale&) {
                                               return "{regularize: true, regularize_exponent: 0, "
                                                      "regularize_roughness: " +
                                                      std::to_string(0.2 * p) + "}";
                                             },
                                             256, Stratified};

const ConsistentCase BpmGlass{GlassSphere, BpmMethod, 8};
const ConsistentCase RegularizedGlass{GlassSphere, RegularizedPathMethod, 8};
const ConsistentCase SppmGlass{GlassSphere, SppmMethod, 6}, PhotonGlass{GlassSphere, StratifiedPhotonMethod, 16},
    FixedPhotonGlass{GlassSphere, FixedRadiusPhotonMethod, 8}, SppmRing{MetalRing, SppmMethod, 8},
    PhotonRing{MetalRing, PhotonMethod, 24}, SppmEnclosed{EnclosedLight, SppmMethod, 3},
    PhotonEnclosed{EnclosedLight, PhotonMethod, 8};

// c from the sweeps (top of the file), rounded up. The levels are the pair
// whose bias is resolved above the noise in every run seen.
// Sweep (8 seeds, stratified 8 × 8 × 64 spp, BDPT 24 seeds): −23.9, −4.09,
// +0.46, −0.93 % at p = 2, 1, 0.5, 0.25 (noise sd 0.44–1.29 %): the blur of
// a fixed disc darkens the caustic's core and vanishes as r shrinks.
// Sweep (8 seeds, stratified 8 × 8 × 4 × 256 spp, α = 0.2 p): −92.7, −73.7,
// −45.2, −17.4 % at p = 4, 2, 1, 0.5 (noise sd 0.4–1.5 %): a rough sphere
// spreads its caustic over the floor, far beyond the caustic's pixels;
// |d|/(ref p) 0.23, 0.37, 0.45, 0.35 → c = 0.5.
TEST(ConsistentCaustic, RegularizedPathOnTheGlassSphere) { expectConsistent(RegularizedGlass, {1, 0.5}, 0.5, Alpha); }
TEST(ConsistentCaustic, BpmOnTheGlassSphere) { expectConsistent(BpmGlass, {1, 0.5}, 0.045, Alpha); }
TEST(ConsistentCaustic, SppmOnTheGlassSphere) { expectConsistent(SppmGlass, {2, 1}, 0.14, Alpha); }
TEST(ConsistentCaustic, SppmOnTheMetalRing) { expectConsistent(SppmRing, {2, 1}, 0.035, Alpha); }
TEST(ConsistentCaustic, PhotonOnTheGlassSphere) { expectConsistent(PhotonGlass, {2, 0.5}, 0.045, Alpha); }
TEST(ConsistentCaustic, PhotonOnTheMetalRing) { expectConsistent(PhotonRing, {2, 0.5}, 0.02, Alpha); }
TEST(ConsistentCaustic, SppmOnTheEnclosedLight) { expectConsistent(SppmEnclosed, {2, 1}, 0.025, Alpha); }
// Its bias is not resolved above the noise at any p swept: the allowance only.
TEST(ConsistentCaustic, PhotonOnTheEnclosedLight) { expectConsistent(PhotonEnclosed, {1}, 0.02, Alpha); }

TEST(ConsistentCaustic, DISABLED_BpmGlassSphereBiasSweep) { printSweep(BpmGlass); }
TEST(ConsistentCaustic, DISABLED_RegularizedPathGlassSphereBiasSweep) { printSweep(RegularizedGlass, {4, 2, 1, 0.5}); }
TEST(ConsistentCaustic, DISABLED_SppmGlassSphereBiasSweep) { printSweep(SppmGlass); }
TEST(ConsistentCaustic, DISABLED_PhotonGlassSphereBiasSweep) { printSweep(PhotonGlass); }
TEST(ConsistentCaustic, DISABLED_FixedRadiusPhotonGlassSphereBiasSweep) { printSweep(FixedPhotonGlass); }
TEST(ConsistentCaustic, DISABLED_SppmMetalRingBiasSweep) { printSweep(SppmRing); }
TEST(ConsistentCaustic, DISABLED_PhotonMetalRingBiasSweep) { printSweep(PhotonRing); }
TEST(ConsistentCaustic, DISABLED_SppmEnclosedLightBiasSweep) { printSweep(SppmEnclosed); }
TEST(ConsistentCaustic, DISABLED_PhotonEnclosedLightBiasSweep) { printSweep(PhotonEnclosed); }

}  // namespace
}  // namespace lb::test
