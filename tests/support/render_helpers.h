#pragma once
// Shared set-up for integrator tests: load a shipped scene at a small size (or a
// scene from text), render it with an integrator, and compare region means.
#include <algorithm>
#include <functional>
#include <memory>
#include <string>
#include "core/film.h"
#include <gtest/gtest.h>
#include "core/scene_loader.h"
#include "integrators/render_loop.h"
#include "tests/support/statistics.h"

namespace lb::test {

std::string sourcePath(const std::string& relative);
// A shipped scene (scenes/NAME.yaml, or scenes/NAME when it ends in .xml or .pbrt)
// with its film resized; extra top-level YAML (e.g. "world_scale: 100") may
// be merged in.
SceneFile loadShippedScene(const std::string& name, int width, int height, const std::string& extraYaml = "");

struct RenderSpec {
  std::string integrator = "path";
  std::string params = "{}";  // YAML mapping of integrator parameters
  uint64_t spp = 16;
  uint64_t seed = 1;
  int threads = 0;            // 0: default
  AdaptiveSettings adaptive = {};  // off unless enabled
};
struct Rendered {
  std::unique_ptr<Film> film;
  RenderReport report;  // passes, rays, NaN/Inf count
};
Rendered renderWithReport(const SceneFile& scene, const RenderSpec& spec);
inline std::unique_ptr<Film> renderScene(const SceneFile& scene, const RenderSpec& spec) {
  return renderWithReport(scene, spec).film;
}

// Means over a grid of rectangular regions, with the variance of each mean
// taken from the film's per-pixel variance estimates (independent pixels).
struct RegionMeans {
  int regionsX = 0, regionsY = 0;
  std::vector<double> mean, varianceOfMean;  // per region and channel: [region * 3 + c]
};
// `mask` (optional, one entry per pixel) keeps only the pixels marked true.
RegionMeans regionMeans(const Film& film, int regionsX, int regionsY, const std::vector<bool>* mask = nullptr);
// Pixels whose camera rays (centre and four corners) all satisfy `keep`,
// given whether the ray hit and what it hit first.
std::vector<bool> primaryHitMask(const Scene& scene, const std::function<bool(bool, const SurfaceInteraction&)>& keep);
// Pixels whose camera rays all first hit a surface with a purely diffuse material.
std::vector<bool> diffusePrimaryHits(const Scene& scene);
// A directly seen caustic's pixels: those of `candidates` at least 3× their
// median, chosen on an independent light-tracing render `selection` (so the
// pixels compared later are not picked by their own noise).
std::vector<bool> causticPixels(const SceneFile& scene, const RenderSpec& selection, const std::vector<bool>& candidates);
inline size_t countTrue(const std::vector<bool>& mask) { return size_t(std::count(mask.begin(), mask.end(), true)); }

// Mean over a rectangle of the film against an exact value: z-test with the
// variance of the mean from the film's per-pixel estimates, plus a float
// rounding allowance that matters only for zero-variance estimators.
::testing::AssertionResult meanMatches(const Film& film, double expected, double alpha, int channel = 0, int x0 = 0,
                                       int y0 = 0, int x1 = -1, int y1 = -1);

// A 16×16 camera looking straight down at a diffuse plane (albedo 0.5) lit by
// a point light of intensity 10 at (0.3, 2, 0.2): the analytic test scene.
extern const char* const PointLightPlaneScene;
// Camera inside a closed, inward-facing sphere of albedo a emitting Le = 1:
// L = Le / (1 - a) everywhere (testing.md §2).
std::string furnaceScene(float albedo);
// Exact pixel-averaged radiance of a diffuse plane y = 0 (albedo rho) under a
// point light (intensity I) for `camera`, by dense quadrature of ρIcosθ/(πr²).
double pointLightOverPlane(const Camera& camera, Vec3 light, float intensity, float rho);

// z-tests of A against B over all regions, Šidák-corrected at level alpha;
// returns a description of every failing region (empty when all pass).
std::string compareRegions(const RegionMeans& a, const RegionMeans& b, double alpha);

// Two scenes that should render alike (an imported scene and one written by
// hand, instanced and flattened shapes, a constant map and the constant
// environment): `spec` on each, the first with spec.seed and the second with
// spec.seed + 1, compared by compareRegions on 4×4 regions at level alpha.
std::string compareScenes(const SceneFile& a, const SceneFile& b, RenderSpec spec, double alpha = 1e-3);

}  // namespace lb::test
