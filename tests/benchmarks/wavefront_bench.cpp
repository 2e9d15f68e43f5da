// The path tracer's two engines side by side (integrators/path/wavefront.h):
// paths/s and rays/s of `path` with engine single_ray and wavefront, on the
// Cornell box, the glass-sphere caustic and the imported water caustic (a
// 55k-triangle mesh), with 1 and 2 threads; and, in the same run, Embree's raw
// rays/s on each scene: camera rays and cosine-distributed rays from the
// camera rays' hits, traced one at a time (rtcIntersect1) and as streams of
// 4096 (rtcIntersect1M), with no shading. path rays/s ÷ raw rays/s is the
// share of time the estimator leaves to Embree.
//   ./build/tests/lightbench_wavefront_bench     (README "The wavefront engine")
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <map>
#include "core/rng.h"
#include "core/sampling.h"
#include "integrators/registry.h"
#include "integrators/render_loop.h"
#include "tests/support/render_helpers.h"

namespace lb {
namespace {

constexpr int Size = 128;  // film side
const char* const Scenes[] = {"cornell-box", "caustic-glass-sphere", "external/water-caustic/scene.xml"};

const SceneFile& scene(int i) {
  static std::map<int, SceneFile> cache;
  if (!cache.count(i)) cache.emplace(i, test::loadShippedScene(Scenes[i], Size, Size));
  return cache.at(i);
}

// state.range(0): scene, range(1): threads.
void Engine(benchmark::State& state, const char* engine) {
  const SceneFile& sf = scene(int(state.range(0)));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(1)));
  Params params(YAML::Load(std::string("{engine: ") + engine + "}"), "", "integrator");
  auto integrator = makeIntegrator("path", params);
  uint64_t rays = 0, paths = 0, pass = 0;
  // One film for every pass, as a render has: a fresh one per iteration (5
  // double layers, 2 MB) cost about 5 % of the Cornell box's time in page
  // faults and zeroing, none of it the estimator's (issue 33's profile).
  Film film(Size, Size);
  for (auto _ : state) {
    RenderOptions options;
    options.seed = pass++;
    options.budget.spp = 4;
    rays += renderLoop(*sf.scene, *integrator, film, sf.sampler, options).rays;
    paths += 4 * Size * Size;
  }
  state.counters["paths/s"] = benchmark::Counter(double(paths), benchmark::Counter::kIsRate);
  state.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
}

// The raw ray mix of one scene: half camera rays, half cosine rays from their hits.
std::vector<Ray> rayMix(const Scene& s) {
  std::vector<Ray> rays;
  Pcg32 rng(7, 7);
  while (rays.size() < (1u << 18)) {
    Ray camera = s.camera.generateRay(Vec2(rng.next1D() * Size, rng.next1D() * Size));
    rays.push_back(camera);
    SurfaceInteraction si;
    if (s.intersect(camera, si)) rays.push_back(si.spawnRay(si.shading.toWorld(sampleCosineHemisphere(rng.next2D()))));
  }
  return rays;
}

// state.range(0): scene, range(1): threads, range(2): 1 = streams of 4096.
void RawEmbree(benchmark::State& state) {
  const Scene& s = *scene(int(state.range(0))).scene;
  static std::map<int, std::vector<Ray>> mixes;
  if (!mixes.count(int(state.range(0)))) mixes.emplace(int(state.range(0)), rayMix(s));
  const std::vector<Ray>& rays = mixes.at(int(state.range(0)));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(1)));
  const bool streams = state.range(2) == 1;
  enableFlushToZeroOnAllThreads();
  uint64_t total = 0;
  for (auto _ : state) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
      if (streams) {
        std::vector<RTCRayHit> rh(r.size());
        for (size_t i = r.begin(); i < r.end(); ++i) Scene::toEmbree(rays[i], rh[i - r.begin()]);
        s.intersect1M(rh.data(), rh.size(), false);
        benchmark::DoNotOptimize(rh.data());
      } else {
        int hits = 0;
        for (size_t i = r.begin(); i < r.end(); ++i) {
          RTCRayHit rh;
          Scene::toEmbree(rays[i], rh);
          s.intersect1(rh);
          hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        }
        benchmark::DoNotOptimize(hits);
      }
    });
    total += rays.size();
  }
  state.counters["rays/s"] = benchmark::Counter(double(total), benchmark::Counter::kIsRate);
}

void sceneAndThreads(benchmark::internal::Benchmark* b) {
  b->ArgNames({"scene", "threads"});
  for (int s = 0; s < 3; ++s)
    for (int t : {1, 2}) b->Args({s, t});
}
void rawArgs(benchmark::internal::Benchmark* b) {
  b->ArgNames({"scene", "threads", "stream"});
  for (int s = 0; s < 3; ++s)
    for (int t : {1, 2})
      for (int stream : {0, 1}) b->Args({s, t, stream});
}

BENCHMARK_CAPTURE(Engine, single_ray, "single_ray")->Apply(sceneAndThreads)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK_CAPTURE(Engine, wavefront, "wavefront")->Apply(sceneAndThreads)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(RawEmbree)->Apply(rawArgs)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);

}  // namespace
}  // namespace lb

BENCHMARK_MAIN();
