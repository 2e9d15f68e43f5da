// Pixel filters in images (core/filter.h): a filtered render of a step edge
// is the filter's convolution of the step, computed here from the filter's
// definition (tests/support/filter_reference.h): pixel column c, whose centre
// is t pixels left of the edge, sees F(t) = ∫_{−∞}^{t} f̂₁. The path tracer
// draws its camera samples from the filter, the light tracer splats through
// it, and BDPT does both under MIS, so all three must give F, up to the
// image's edges (where a wide filter reaches past them into the margin the
// camera sees: the left columns are 1 only if the splats there count).
#include <gtest/gtest.h>
#include <functional>
#include <sstream>
#include "core/scene_loader.h"
#include "tests/support/filter_reference.h"
#include "tests/support/render_helpers.h"
#include "tests/support/statistics.h"

namespace lb {
namespace {

using test::FilterCase;

// A 16×4 film whose camera (a pinhole at the origin looking down −z, the
// image spanning x in [−½, ½] at z = −1) sees an emitter of radiance 1 on
// the left half (x in [−0.7, 0]) and nothing on the right, the margin of
// every filter below included; the edge is at raster x = 8.
std::string stepEdgeScene(const FilterCase& c) {
  std::ostringstream s;
  s << "camera: {position: [0, 0, 0], look_at: [0, 0, -1], fov: 53.13010235415598, fov_axis: x}\n"
    << "film: {width: 16, height: 4, filter: {type: " << PixelFilter::names()[size_t(c.type)]
    << ", radius: " << c.radius;
  if (c.type == PixelFilter::Type::Gaussian) s << ", sigma: " << c.a;
  if (c.type == PixelFilter::Type::Mitchell) s << ", b: " << c.a << ", c: " << c.b;
  if (c.type == PixelFilter::Type::Lanczos) s << ", tau: " << c.a;
  s << "}}\n"
    << "materials: {black: {type: diffuse, albedo: [0, 0, 0]}}\n"
    << "shapes:\n"
    << "  - {type: rectangle, material: black, emission: [1, 1, 1],\n"
    << "     transform: {scale: [0.35, 0.4, 1], translate: [-0.35, 0, -1]}}\n";
  return s.str();
}

// The filters the image tests use: the one-pixel box, and wider ones with
// and without negative lobes.
std::vector<FilterCase> imageCases() {
  std::vector<FilterCase> cases;
  for (const FilterCase& c : test::filterCases())
    if (c.name == "box" || c.name == "wide_tent" || c.name == "gaussian" || c.name == "mitchell" || c.name == "lanczos")
      cases.push_back(c);
  return cases;
}

struct FilmRun {
  const char* integrator;
  const char* params;
  uint64_t spp;
};

// Each column's mean over its rows (green) against want(t), t the column
// centre's distance left of the edge, by z-tests from the film's variance.
void expectColumns(const std::string& scene, const FilterCase& c, const FilmRun& run, double zMax,
                   const std::function<double(double)>& want) {
  SceneFile sf = loadSceneFromString(scene, "step-edge.yaml");
  auto film = test::renderScene(sf, {run.integrator, run.params, run.spp, 3});
  Image mean = film->image(), variance = film->varianceOfMean();
  const int W = mean.width, H = mean.height;
  for (int x = 0; x < W; ++x) {
    double m = 0, v = 0;
    for (int y = 0; y < H; ++y) m += mean.at(x, y).g / H, v += variance.at(x, y).g / (H * H);
    double expected = want(W / 2.0 - (x + 0.5));
    EXPECT_LT(std::abs(test::zScore(m, v, expected, 0)), zMax)
        << c.name << ", " << run.integrator << " " << run.params << ", column " << x << ": " << m << " vs " << expected
        << " (±" << std::sqrt(v) << ")";
  }
}

// An emitter of radiance 1 on the left: the path tracer's camera samples and
// the light tracer's splats (its emitter points connected to the camera).
TEST(PixelFilterImage, AStepEdgeIsTheFiltersConvolutionOfIt) {
  const auto cases = imageCases();
  const std::vector<FilmRun> runs = {{"path", "{}", 1024}, {"light", "{}", 1024}, {"bdpt", "{}", 512}};
  const double zMax = test::normalCritical(test::sidak(1e-3, int(cases.size() * runs.size()) * 16));
  for (const FilterCase& c : cases)
    for (const FilmRun& run : runs)
      expectColumns(stepEdgeScene(c), c, run, zMax, [&](double t) { return test::filterReferenceCdf(c, t); });
}

// A diffuse surface of albedo ½ on the left under a uniform sky of radiance
// 1, the sky itself on the right: 1 − ½·F(t). BDPT's and VCM's t = 1
// strategies (a light vertex on the surface, splatted) now carry part of the
// image under MIS, beside the camera's filtered samples.
TEST(PixelFilterImage, AReflectedStepEdgeAgreesUnderMis) {
  const auto cases = imageCases();
  const std::vector<FilmRun> runs = {{"path", "{}", 512}, {"bdpt", "{}", 512}, {"vcm", "{mode: bpt}", 512}};
  const double zMax = test::normalCritical(test::sidak(1e-3, int(cases.size() * runs.size()) * 16));
  for (const FilterCase& c : cases) {
    std::string scene = stepEdgeScene(c);
    scene.replace(scene.find("albedo: [0, 0, 0]"), 17, "albedo: [0.5, 0.5, 0.5]");
    scene.replace(scene.find("emission: [1, 1, 1],"), 20, "");
    scene += "lights: [{type: environment, radiance: 1}]\n";
    for (const FilmRun& run : runs)
      expectColumns(scene, c, run, zMax, [&](double t) { return 1 - 0.5 * test::filterReferenceCdf(c, t); });
  }
}

// The Cornell box under a filter with negative lobes (Lanczos): BDPT (its t = 1
// strategies splatted, the rest filtered camera samples, under MIS) against
// the light tracer (all splats) and the path tracer (no splats), region by
// region within the films' measured variance.
TEST(PixelFilterImage, BdptAgreesWithLightAndPathTracingInTheCornellBox) {
  SceneFile sf = test::loadShippedScene("cornell-box", 24, 24, "film: {width: 24, height: 24, filter: {type: lanczos}}");
  auto bdpt = test::renderScene(sf, {"bdpt", "{}", 1024, 5});
  auto light = test::renderScene(sf, {"light", "{}", 1024, 6});
  auto path = test::renderScene(sf, {"path", "{}", 1024, 7});
  EXPECT_EQ(test::compareRegions(test::regionMeans(*bdpt, 4, 4), test::regionMeans(*light, 4, 4), 1e-3), "");
  EXPECT_EQ(test::compareRegions(test::regionMeans(*bdpt, 4, 4), test::regionMeans(*path, 4, 4), 1e-3), "");
}

TEST(PixelFilterImage, TheSceneFileRefusesAFilterThatCannotBeNormalised) {
  // A Lanczos window of τ = 10⁻⁴ lobes: ∫ f₁ ≈ τ, nothing left to normalise.
  FilterCase bad{"lanczos", PixelFilter::Type::Lanczos, 3, 1e-4};
  EXPECT_THROW(loadSceneFromString(stepEdgeScene(bad), "bad.yaml"), ConfigError);
  FilterCase unknownKey{"box", PixelFilter::Type::Box, 0.5};
  std::string text = stepEdgeScene(unknownKey);
  text.replace(text.find("radius"), 6, "sigma");  // a Gaussian's key on a box
  EXPECT_THROW(loadSceneFromString(text, "bad.yaml"), ConfigError);
}

}  // namespace
}  // namespace lb
