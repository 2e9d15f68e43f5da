#pragma once
// Sub-commands of the `lightbench` program. Each returns the process exit code:
// 0 success, 1 runtime failure, 2 bad input (a ConfigError, with file:line:key).
#include <CLI/CLI.hpp>
#include <yaml-cpp/yaml.h>
#include <functional>
#include <string>
#include <vector>
#include "core/film.h"
#include "core/image.h"
#include "experiments/cluster.h"
#include "integrators/render_loop.h"

namespace lb {

struct RenderArgs {
  std::string scene;
  std::string integrator;              // empty: the scene's, else "path"
  std::vector<std::string> overrides;  // key=value for the integrator
  uint64_t spp = 0;
  double seconds = 0;
  uint64_t seed = 0;
  int threads = 0;                     // 0: all cores
  std::string output;
  std::string replayPixel;             // "X,Y"
  long long replaySample = -1;
  bool quiet = false;
  double worldScale = 0;               // > 0: the scene scaled (camera, lights and radii too)
  bool strict = false;                 // an imported scene's unsupported elements are errors
  std::string resolution;              // "WxH": replaces the scene's film size
  std::string crop;                    // "X0,Y0,X1,Y1": render only these pixels of the film
  float exposure = 0;                  // the PNG preview's, in stops
  std::vector<std::string> aovs;       // layers: albedo, normal, depth, variance, spp
  std::string sampler;                 // replaces the scene's sampler type
  bool adaptive = false;               // adaptive sampling (integrators/adaptive_sampling.h)
  int adaptivePasses = 8;
  double adaptiveTarget = 0;
  // --distributed (issue 19): the render as seeded chunks of chunkSpp passes
  // (experiments/chunks.h), under MPI spread over the ranks; the same bits
  // with any number of ranks, one included.
  bool distributed = false;
  uint64_t chunkSpp = 16;
  Farm* farm = nullptr;  // under MPI with more than one rank
  // Called on the rendering thread between passes (not timed); it may throw
  // to stop the render: the Python package raises KeyboardInterrupt there.
  std::function<void()> betweenPasses;
};

// The AOV names --aov accepts.
const std::vector<std::string>& aovNames();

// Runs a command body: a ConfigError prints "error: file:line: key: ..." and
// gives exit code 2, any other exception exit code 1.
int withErrorExitCodes(const std::function<int()>& body);

int runRender(const RenderArgs& args);
// A worker rank's side of `render --distributed`: renders the chunks rank 0
// hands out; returns rank 0's exit code.
int serveRender(const RenderArgs& args);

// A render held in memory: what `lightbench render` writes, before writing
// (the Python package's render() returns it as an array and a dict).
struct RenderedImage {
  Image image;
  YAML::Node resolved;       // the resolved configuration ...
  std::string resolvedYaml;  // ... as <name>.config.yaml holds it
  RenderReport report;
  std::vector<NonFiniteSample> firstNonFinite;  // to replay with --pixel/--sample
  std::vector<ExrLayer> layers;                 // the AOVs asked for, then the integrator's layers
  std::map<std::string, std::string> attributes;  // the EXR header's lightbench/* metadata
  std::vector<std::string> integratorSummary;     // the integrator's own estimates (MLT's b), for the summary
};
// Loads, renders within the budget and returns the image; throws ConfigError
// for bad input. args.output and the replay fields are not used.
RenderedImage renderToMemory(const RenderArgs& args);

struct RunArgs {
  std::string experiment;
  bool quick = false, resume = false, noReport = false;
  int jobs = 1;
  std::string results = "results";
  std::string python;  // the report's interpreter
  int threads = 0;     // per run (0: cores / jobs, or a node's cores / its worker ranks)
  bool mixedMachines = false;
  Farm* farm = nullptr;  // under MPI with more than one rank
  // Called on the rendering thread between passes (not timed); it may throw
  // to stop the render: the Python package raises KeyboardInterrupt there.
  std::function<void()> betweenPasses;
};
int runExperimentCommand(const RunArgs& args);

// `lightbench verdict RUN`: the run folder's verdict files again
// (experiments/verdict/run_folder.h), with other settings if given, and its report.
struct VerdictArgs {
  std::string run;
  std::string rankBy, baseline;  // empty: as the run's meta.json says
  double confidence = 0;         // 0: as meta.json says
  bool noReport = false;
  std::string python;
};
int verdictCommand(const VerdictArgs& args);
int serveExperimentCommand(const RunArgs& args);  // a worker rank's side
// `farm`: this process is one of several MPI ranks (experiments/cli/main.cpp).
int lightbenchMain(int argc, char** argv, Farm* farm = nullptr);
// The bash completion script for `app` (completion.cpp).
std::string bashCompletion(const CLI::App& app);
std::string versionString();

}  // namespace lb
