// The bidirectional family's cost (part of lightbench_bench, issue 33):
// a VCM iteration per mode, and where the time of a BDPT sample and of a VCM
// iteration goes (bidir::CostSplit: light subpaths, the merging index,
// camera subpaths, connections, merges, MIS weights; each exclusive of the
// others, in milliseconds of the pass's wall time: thread time ÷ threads).
//   ./build/tests/lightbench_bench --benchmark_filter='VcmIteration|CostSplit'
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>
#include <chrono>
#include <map>
#include "integrators/bidirectional/cost_split.h"
#include "integrators/registry.h"
#include "integrators/vcm/vcm.h"
#include "tests/support/render_helpers.h"

namespace lb {
namespace {

const SceneFile& scene128(const std::string& name) {
  static std::map<std::string, SceneFile> scenes;
  if (!scenes.count(name)) scenes.emplace(name, test::loadShippedScene(name, 128, 128));
  return scenes.at(name);
}

// VCM iterations (one light and one camera subpath per pixel, 128², the
// Cornell box with spheres) per mode, uninstrumented. bpt against vcm shows
// what merging costs; the *_flann rows use FLANN's kd-tree for the lookup.
void VcmIteration(benchmark::State& state, const char* settings) {
  const SceneFile& sf = scene128("cornell-box-spheres");
  Params params(YAML::Load(settings), "", "integrator");
  Vcm vcm(VcmSettings::read(params));
  Film film(128, 128);
  auto sampler = makeSampler(sf.sampler, 1);
  PassStats stats;
  uint64_t pass = 0;
  enableFlushToZeroOnAllThreads();
  for (auto _ : state) vcm.renderPass(*sf.scene, film, *sampler, pass++, stats);
  state.counters["iterations/s"] = benchmark::Counter(double(pass), benchmark::Counter::kIsRate);
}
BENCHMARK_CAPTURE(VcmIteration, vcm, "{mode: vcm}")->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);
BENCHMARK_CAPTURE(VcmIteration, bpm, "{mode: bpm}")->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);
BENCHMARK_CAPTURE(VcmIteration, ppm, "{mode: ppm}")->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);
BENCHMARK_CAPTURE(VcmIteration, bpt, "{mode: bpt}")->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);
BENCHMARK_CAPTURE(VcmIteration, vcm_flann, "{mode: vcm, lookup: flann}")->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);
BENCHMARK_CAPTURE(VcmIteration, bpm_flann, "{mode: bpm, lookup: flann}")->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);
BENCHMARK_CAPTURE(VcmIteration, ppm_flann, "{mode: ppm, lookup: flann}")->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);

// One pass (a BDPT sample or a VCM iteration per pixel, 128²) with the cost
// split on: each phase's milliseconds per pass, "other" for what no phase
// claims (adding splats, the film), and "ms/pass" for the pass's wall time
// with the instrumentation, against which the uninstrumented rows above
// (and Integrator/bdpt_*) show its overhead.
void CostSplit(benchmark::State& state, const char* integrator, const char* scene, const char* settings = "{}") {
  const SceneFile& sf = scene128(scene);
  Params params(YAML::Load(settings), "", "integrator");
  auto integ = makeIntegrator(integrator, params);
  Film film(128, 128);
  auto sampler = makeSampler(sf.sampler, 1);
  PassStats stats;
  uint64_t pass = 0;
  enableFlushToZeroOnAllThreads();
  bidir::CostSplit::enable(true);
  auto start = std::chrono::steady_clock::now();
  for (auto _ : state) integ->renderPass(*sf.scene, film, *sampler, pass++, stats);
  double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  auto seconds = bidir::CostSplit::threadSeconds();
  bidir::CostSplit::enable(false);
  double threads = tbb::this_task_arena::max_concurrency(), passes = double(std::max<uint64_t>(pass, 1));
  double claimed = 0;
  for (int p = 1; p < bidir::PhaseCount; ++p) {
    double ms = 1e3 * seconds[size_t(p)] / threads / passes;
    claimed += ms;
    state.counters[std::string(bidir::phaseName(bidir::Phase(p))) + " ms"] = ms;
  }
  state.counters["other ms"] = 1e3 * wall / passes - claimed;
  state.counters["ms/pass"] = 1e3 * wall / passes;
}
BENCHMARK_CAPTURE(CostSplit, bdpt_cornell_spheres, "bdpt", "cornell-box-spheres")->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);
BENCHMARK_CAPTURE(CostSplit, vcm_cornell_spheres, "vcm", "cornell-box-spheres")->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);
BENCHMARK_CAPTURE(CostSplit, bpm_cornell_spheres, "vcm", "cornell-box-spheres", "{mode: bpm}")->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);
BENCHMARK_CAPTURE(CostSplit, ppm_cornell_spheres, "vcm", "cornell-box-spheres", "{mode: ppm}")->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);
BENCHMARK_CAPTURE(CostSplit, bdpt_caustic, "bdpt", "caustic-glass-sphere")->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);
BENCHMARK_CAPTURE(CostSplit, vcm_caustic, "vcm", "caustic-glass-sphere")->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);

}  // namespace
}  // namespace lb
