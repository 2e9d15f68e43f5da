#pragma once
// Stochastic progressive photon mapping (Hachisuka & Jensen 2009). Each pass:
//  1. a camera pass finds, per pixel, the first non-specular surface through
//     specular bounces (the visible point) and adds emission seen that way and
//     direct light by NEE;
//  2. a photon pass traces photons_per_pass photons; every photon landing
//     (after its first bounce: direct light is NEE's) within a visible point's
//     radius R adds β·f·Φ·|ω·n_s|/|ω·n_g| to that pixel's flux (shading
//     normals: photon_map.h), if the joined path is at most max_depth
//     segments (path_length.h);
//  3. per pixel, with M new photons and flux Φ:
//        N' = N + αM,  R' = R·sqrt((N + αM)/(N + M)),  τ' = (τ + Φ)·R'²/R²,
//     and the photon term of the pixel is τ / (N_emitted π R²).
// The radius shrinks while N grows, so the estimate is consistent: its error
// keeps falling with time.
//
//   photons_per_pass  100000
//   alpha             0.7     fraction of new photons kept (0, 1)
//   initial_radius    0       world units; 0: relative_radius × the scene's bounding radius
//   relative_radius   0.02
//   max_depth         32      total path length in segments, camera to light (path_length.h)
//   lookup            grid    grid | flann: how photons find the visible points
//
// Lookup: `grid` hashes each visible point into every cell its radius ball
// overlaps (cell size = the largest radius; pbrt-v3 §16.2.3), so a photon
// reads one cell; `flann` searches a kd-tree over the visible points at the
// largest radius and filters by each point's own radius. Measured with
// `lightbench_bench --benchmark_filter=Sppm` (README): one pass on the Cornell
// box with spheres at 128², 100k photons: grid 50.1 ms, FLANN 48.9 ms (FLANN
// 2 % faster, within run-to-run noise); at 256² (20 passes, `lightbench
// render`) grid 1.79 s, FLANN 1.96 s (grid 9 % faster). A tie overall; the
// grid is the default as the simpler structure with no kd-tree build. Both
// find the same points (a test checks bit-identical images).
#include "core/params.h"
#include "integrators/integrator.h"

namespace lb {

struct SppmSettings {
  size_t photonsPerPass = 100000;
  float alpha = 0.7f;
  float initialRadius = 0, relativeRadius = 0.02f;
  int maxDepth = 32;
  bool gridLookup = true;
  static SppmSettings read(Params& p);
};

// One pixel's progressive statistics and their update (step 3 above).
struct SppmPixel {
  double N = 0;
  float R = 0;
  glm::dvec3 tau{0.0};
  void update(double newPhotons, const glm::dvec3& newFlux, float alpha) {
    if (newPhotons <= 0) return;
    double N2 = N + alpha * newPhotons;
    float R2 = R * float(std::sqrt(N2 / (N + newPhotons)));
    tau = (tau + newFlux) * double(R2 * R2) / double(R * R);
    N = N2, R = R2;
  }
};

class Sppm final : public Integrator {
 public:
  std::string splitRefusal() const override {
    return "each pass shrinks its radii from the photons of the passes before; the mean of chunks keeps the bias "
           "of one chunk's passes";
  }
  explicit Sppm(SppmSettings s) : settings_(s) {}
  void renderPass(const Scene& scene, Film& film, const Sampler& prototype, uint64_t pass, PassStats& stats) override;
  const std::vector<SppmPixel>& pixels() const { return pixels_; }

 private:
  SppmSettings settings_;
  std::vector<SppmPixel> pixels_;
  uint64_t photonsEmitted_ = 0;
};

}  // namespace lb
