// Density estimation against closed forms (testing.md §2, §5): the k-nearest
// estimate on uniform photons, and the photon terms of photon mapping and SPPM
// in the furnace, where the answer is exact and density estimation has no
// geometric bias.
#include <gtest/gtest.h>
#include <iostream>
#include "core/rng.h"
#include "integrators/photon/photon_integrator.h"
#include "integrators/sppm/sppm.h"
#include "tests/support/render_helpers.h"

namespace lb::test {
namespace {

constexpr double Alpha = 1e-3;

// Uniform photons on the unit square (z = 0, arriving along the normal), of
// total power 1: the flux density is exactly 1 everywhere. The k-nearest
// estimate at interior points, with any filter, must average to 1: for a
// Poisson (or binomial) point set π r_k² λ ~ Gamma(k, 1) (Beta(k, N − k + 1)
// in area fraction), so E[1/(π r_k²)] = λ/(k − 1), and an estimator that
// counts all k photons over π r_k² is biased by k/(k − 1): +14 % at k = 8.
// Query points 0.1 apart with discs of radius ~0.025 see disjoint photons, so
// their estimates are (nearly) independent; 20 photon sets give 1620 of them
// and the bound is a t-test on their measured variance. Also with maxRadius
// near the median r_k, so that half the queries use the fixed disc instead.
TEST(PhotonDensity, KNearestEstimateIsUnbiasedForUniformDensity) {
  const size_t N = 4000, k = 8;
  const float medianRadius = std::sqrt((k - 0.33f) / (Pi * N));  // Gamma(k)'s median ≈ k − 1/3
  const PhotonFilter filters[3] = {PhotonFilter::Box, PhotonFilter::Cone, PhotonFilter::Epanechnikov};
  const char* names[3] = {"box", "cone", "epanechnikov"};
  RunningStats stats[3][2];
  std::vector<std::pair<size_t, float>> scratch;
  SurfaceInteraction x;
  x.ng = Vec3(0, 0, 1), x.shading = Frame(x.ng);
  for (uint64_t set = 0; set < 20; ++set) {
    Pcg32 rng(set, 11);
    std::vector<Photon> photons(N);
    for (Photon& ph : photons) ph = {Vec3(rng.next1D(), rng.next1D(), 0), Vec3(0, 0, 1), Color(1.f / N), Vec3(0, 0, 1), 1};
    PhotonMap map(std::move(photons));
    for (int i = 1; i <= 9; ++i)
      for (int j = 1; j <= 9; ++j) {
        x.p = Vec3(0.1f * i, 0.1f * j, 0);
        for (int f = 0; f < 3; ++f)
          for (int bounded = 0; bounded < 2; ++bounded) {
            DensityQuery q{k, bounded ? medianRadius : Infinity, filters[f]};
            stats[f][bounded].add(map.radiance(x, q, 1, [](const Vec3&) { return Color(1.f); }, scratch).r);
          }
      }
  }
  double t = studentCritical(sidak(Alpha, 6), stats[0][0].n - 1);
  std::cout << "k = " << k << ", box filter: mean " << stats[0][0].mean << " ± " << std::sqrt(stats[0][0].varianceOfMean())
            << " (exact 1)\n";
  for (int f = 0; f < 3; ++f)
    for (int bounded = 0; bounded < 2; ++bounded) {
      const RunningStats& s = stats[f][bounded];
      EXPECT_LE(std::abs(s.mean - 1), t * std::sqrt(s.varianceOfMean()))
          << names[f] << (bounded ? ", maxRadius at the median r_k" : "") << ": mean " << s.mean << " ± "
          << std::sqrt(s.varianceOfMean()) << " (k/(k−1) = " << double(k) / (k - 1) << ")";
    }
}

// The furnace (scenes/extremes/furnace.yaml): inside a closed sphere of albedo
// a = 1/2 emitting 1, a path of n segments carries a^(n−1), so at max_depth D
// the image is Σ_{n=1..D} a^(n−1) everywhere. On a sphere the surface inside
// a ball of radius r around a surface point has area exactly π r²
// (Archimedes), and the photon density is uniform: density estimation has no
// bias here, so the bounds are purely statistical (t-tests on independent
// seeds, whose spread includes the noise frozen into each photon map).
double furnace(int maxDepth, int fromSegments = 1) {
  double sum = 0;
  for (int n = fromSegments; n <= maxDepth; ++n) sum += std::pow(0.5, n - 1);
  return sum;
}

// SPPM's photon term alone: camera paths of 1 segment, photons of at least
// 2 (direct light is NEE's), so at max_depth 4 it is a² + a³ = 0.375 (the
// path-length rule of path_length.h; bounding photons by max_depth on their
// own would give a² + a³ + a⁴ = 0.4375). Read from the progressive
// statistics: τ / (N_emitted π R²) per pixel (Hachisuka & Jensen 2009).
TEST(SppmPhotonTerm, FurnaceMatchesTheClosedForm) {
  const int Size = 32, Seeds = 8, Passes = 4;
  SceneFile sf = loadShippedScene("extremes/furnace", Size, Size);
  RunningStats photonTerm, total;
  for (int seed = 0; seed < Seeds; ++seed) {
    SppmSettings s;
    s.photonsPerPass = 5000, s.maxDepth = 4;
    Sppm sppm(s);
    Film film(Size, Size);
    RenderOptions o;
    o.seed = 40 + uint64_t(seed);
    o.budget.spp = Passes;
    renderLoop(*sf.scene, sppm, film, sf.sampler, o);
    double sum = 0;
    for (const SppmPixel& p : sppm.pixels()) sum += p.tau.x / (double(Passes) * s.photonsPerPass * Pi * p.R * p.R);
    photonTerm.add(sum / double(sppm.pixels().size()));
    total.add(regionMeans(film, 1, 1).mean[0]);
  }
  double t = studentCritical(sidak(Alpha, 2), Seeds - 1);
  std::cout << "SPPM furnace, max_depth 4: photon term " << photonTerm.mean << " ± " << std::sqrt(photonTerm.varianceOfMean())
            << " (exact " << furnace(4, 3) << "), image " << total.mean << " ± " << std::sqrt(total.varianceOfMean())
            << " (exact " << furnace(4) << ")\n";
  EXPECT_LE(std::abs(photonTerm.mean - furnace(4, 3)), t * std::sqrt(photonTerm.varianceOfMean()))
      << "photon term " << photonTerm.mean << " vs " << furnace(4, 3);
  EXPECT_LE(std::abs(total.mean - furnace(4)), t * std::sqrt(total.varianceOfMean()))
      << "image " << total.mean << " vs " << furnace(4);
}

// Photon mapping with final_gather 0 shows the global map at the first
// surface: with the box filter, k = 8, at max_depth 4 the image must be
// 1 + a + a² + a³ = 1.875 (photons of up to 3 segments). Counting the k-th
// photon would give 1 + 0.875·8/7 = 2.0; photons bounded by max_depth alone
// 1 + 0.9375·8/7.
TEST(PhotonMapper, FurnaceGlobalMapMatchesTheClosedForm) {
  SceneFile sf = loadShippedScene("extremes/furnace", 8, 8);
  RunningStats image;
  for (uint64_t seed = 0; seed < 8; ++seed) {
    Rendered r = renderWithReport(
        sf, {"photon", "{global_photons: 5000, caustic_photons: 0, k: 8, max_radius: 1, filter: box, final_gather: 0, max_depth: 4}", 1, 60 + seed});
    image.add(regionMeans(*r.film, 1, 1).mean[0]);
  }
  double t = studentCritical(Alpha, image.n - 1);
  std::cout << "photon furnace, box filter, k = 8, max_depth 4: " << image.mean << " ± " << std::sqrt(image.varianceOfMean())
            << " (exact " << furnace(4) << ")\n";
  EXPECT_LE(std::abs(image.mean - furnace(4)), t * std::sqrt(image.varianceOfMean()))
      << "image " << image.mean << " ± " << std::sqrt(image.varianceOfMean()) << " vs " << furnace(4);
}

}  // namespace
}  // namespace lb::test
