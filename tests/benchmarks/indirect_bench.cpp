// Time to reach a given RMSE of the INDIRECT component on the diffuse Cornell
// box: path tracing vs irradiance caching vs photon-map final gathering, with
// and without the cache. Direct light is left out of every estimate, so only
// the estimators of indirect light are compared.
//
// At the first surface seen through each pixel (diffuse, not an emitter) the
// indirect radiance is L = f·E. The points are offset from the pixel centres
// by (0.37, 0.61) of a pixel: centres fall exactly on the box's edges and
// diagonals, where a point belongs to no single surface and a ray leaving it
// can slip out between two separate rectangles. The reference E comes from two
// fine path-traced records (64×128 strata) per point; their difference gives
// the reference's noise, subtracted from every MSE.
//   path         one cosine-sampled path per point per pass (the path tracer
//                beyond its direct-light term), until the RMSE reaches the target
//   photon FG    the same with one final-gather ray into the global map
//   cache        the irradiance_cache integrator rendering the image (prepass +
//                1 spp), then queried at the points; one run per a
// Every timing is wall-clock on all cores.
//   ./build/tests/lightbench_indirect_bench [--size 128] [--target 0.0025]
#include <CLI/CLI.hpp>
#include <tbb/parallel_for.h>
#include <chrono>
#include <cstdio>
#include <yaml-cpp/yaml.h>
#include "core/bsdfs/bsdf.h"
#include "core/sampling.h"
#include "integrators/irradiance_cache/irradiance_cache_integrator.h"
#include "integrators/render_loop.h"
#include "tests/support/render_helpers.h"

namespace lb {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct Point {
  SurfaceInteraction si;
  Vec3 n;
  Color f;  // the Lambertian BSDF value ρ/π
};

std::unique_ptr<IrradianceCacheIntegrator> makeCache(const std::string& yaml, const SceneFile& sf, uint64_t seed) {
  Params p(YAML::Load(yaml), "<bench>", "integrator");
  auto ic = std::make_unique<IrradianceCacheIntegrator>(IrradianceCacheSettings::read(p));
  ic->preprocess(*sf.scene, *makeSampler(sf.sampler, seed));
  return ic;
}

struct Study {
  const SceneFile& sf;
  std::vector<Point> points;
  std::vector<Color> reference;
  double referenceVariance = 0;  // mean over points and channels, of the reference's mean

  double rmse(const std::vector<Color>& L) const {
    double se = 0;
    for (size_t i = 0; i < points.size(); ++i)
      for (int c = 0; c < 3; ++c) se += sqr(L[i][c] - reference[i][c]);
    return std::sqrt(std::max(0.0, se / double(3 * points.size()) - referenceVariance));
  }

  // Progressive one-sample-per-pass estimates of the indirect radiance with a
  // base estimator; prints the time at which the RMSE reaches `target`.
  void progressive(const char* name, const IrradianceCacheIntegrator& ic, double setupSeconds, double target,
                   double timeLimit) const {
    std::vector<Color> sum(points.size(), Color(0.f)), mean(points.size());
    double seconds = setupSeconds, lastRmse = 0;
    for (uint64_t pass = 0;; ++pass) {
      auto t0 = Clock::now();
      tbb::parallel_for(size_t(0), points.size(), [&](size_t i) {
        IndependentSampler s(17);
        s.start(i, pass);
        const Point& p = points[i];
        Vec3 wi = Frame(p.n).toWorld(sampleCosineHemisphere(s.get2D()));
        uint64_t rays = 0;
        sum[i] += p.f * Pi * ic.incident(p.si.spawnRay(wi), s, 31, rays).L;  // f·E with E ≈ π L (cosine pdf)
      });
      seconds += since(t0);
      for (size_t i = 0; i < points.size(); ++i) mean[i] = sum[i] / float(pass + 1);
      double r = rmse(mean);
      if (r <= target) {
        std::printf("%-22s %8.2f s  to RMSE %.4f (%llu samples per point)\n", name, seconds, r, (unsigned long long)pass + 1);
        return;
      }
      if (seconds > timeLimit) {
        std::printf("%-22s not reached in %.0f s: RMSE %.4f (%llu samples per point)%s\n", name, seconds, r,
                    (unsigned long long)pass + 1, pass > 8 && r > 0.95 * lastRmse ? ", stalled (bias)" : "");
        return;
      }
      if (pass % 8 == 0) lastRmse = r;
    }
  }

  // The irradiance_cache integrator renders the image (prepass + 1 spp); the
  // cache is then queried at the points (a miss computes a record, as the
  // integrator would).
  void cached(const std::string& name, const std::string& yaml) const {
    Params p(YAML::Load(yaml), "<bench>", "integrator");
    IrradianceCacheIntegrator ic(IrradianceCacheSettings::read(p));
    Film film(sf.scene->camera.width(), sf.scene->camera.height());
    RenderOptions options;
    options.seed = 3;
    options.budget.spp = 1;
    auto t0 = Clock::now();
    renderLoop(*sf.scene, ic, film, sf.sampler, options);
    std::vector<Color> L(points.size());
    tbb::parallel_for(size_t(0), points.size(), [&](size_t i) {
      LocalRecords none;
      Color E;
      if (!ic.cache().interpolate(points[i].si.p, points[i].n, none, E)) {
        uint64_t rays = 0;
        E = ic.computeRecordAt(points[i].si, hashValues(99, i), 31, rays).E;
      }
      L[i] = points[i].f * E;
    });
    double seconds = since(t0);
    std::printf("%-22s %8.2f s  RMSE %.4f  (%zu records, %.0f records/s of thread time)\n", name.c_str(), seconds,
                rmse(L), ic.cache().size(), double(ic.cache().size()) / std::max(ic.stats().recordSeconds, 1e-9));
  }
};

int run(int argc, char** argv) {
  CLI::App app{"time to a given RMSE of the indirect component, Cornell box"};
  int size = 128;
  double target = 0.0025, timeLimit = 120;
  app.add_option("--size", size, "image width and height");
  app.add_option("--target", target, "RMSE of the indirect radiance to reach");
  app.add_option("--time-limit", timeLimit, "seconds before a progressive method gives up");
  CLI11_PARSE(app, argc, argv);
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // progress visible when redirected

  SceneFile sf = test::loadShippedScene("cornell-box", size, size);
  Study study{sf, {}, {}, 0};
  const Camera& cam = sf.scene->camera;
  for (int y = 0; y < cam.height(); ++y)
    for (int x = 0; x < cam.width(); ++x) {
      SurfaceInteraction si;
      if (!sf.scene->intersect(cam.generateRay(Vec2(x + 0.37f, y + 0.61f)), si) || si.emitter || !si.material) continue;
      Vec3 n = glm::dot(si.wo, si.shading.n) < 0 ? -si.shading.n : si.shading.n;
      study.points.push_back({si, n, BSDF(si).eval(si.wo, n, TransportMode::Radiance).f});
    }

  auto t0 = Clock::now();
  auto fine = makeCache("{theta_strata: 64, phi_strata: 128, prepass_levels: 0}", sf, 11);
  std::vector<Color> a(study.points.size()), b(study.points.size());
  tbb::parallel_for(size_t(0), study.points.size(), [&](size_t i) {
    uint64_t rays = 0;
    a[i] = study.points[i].f * fine->computeRecordAt(study.points[i].si, 2 * i, 31, rays).E;
    b[i] = study.points[i].f * fine->computeRecordAt(study.points[i].si, 2 * i + 1, 31, rays).E;
  });
  double meanL = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    study.reference.push_back(0.5f * (a[i] + b[i]));
    for (int c = 0; c < 3; ++c) study.referenceVariance += 0.25 * sqr(a[i][c] - b[i][c]), meanL += study.reference[i][c];
  }
  study.referenceVariance /= double(3 * a.size());
  meanL /= double(3 * a.size());
  std::printf("Cornell box %dx%d: %zu diffuse points, mean indirect radiance %.4f; reference in %.1f s, its RMSE %.4f\n",
              size, size, study.points.size(), meanL, since(t0), std::sqrt(study.referenceVariance));
  std::printf("target RMSE %.4f (%.1f%% of the mean)\n\n", target, 100 * target / meanL);

  auto pathBase = makeCache("{prepass_levels: 0}", sf, 5);
  study.progressive("path", *pathBase, 0, target, timeLimit);
  auto t1 = Clock::now();
  auto photonBase = makeCache("{base: photon, prepass_levels: 0}", sf, 5);
  study.progressive("photon FG (200k)", *photonBase, since(t1), target, timeLimit);
  t1 = Clock::now();
  auto photonBig = makeCache("{base: photon, prepass_levels: 0, global_photons: 2000000, caustic_photons: 0}", sf, 5);
  study.progressive("photon FG (2M)", *photonBig, since(t1), target, timeLimit);
  for (const char* a : {"0.3", "0.15", "0.08"})
    study.cached(std::string("cache path a=") + a, std::string("{record_image: false, a: ") + a + "}");
  for (const char* a : {"0.3", "0.15", "0.08"})
    study.cached(std::string("cache photon a=") + a, std::string("{base: photon, a: ") + a + "}");
  study.cached("cache path a=0.15 32x96", "{a: 0.15, theta_strata: 32, phi_strata: 96}");
  return 0;
}

}  // namespace
}  // namespace lb

int main(int argc, char** argv) { return lb::run(argc, argv); }
