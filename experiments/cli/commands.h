#pragma once
// Sub-commands of the `lightbench` program. Each returns the process exit code:
// 0 success, 1 runtime failure, 2 bad input (a ConfigError, with file:line:key).
#include <functional>
#include <string>
#include <vector>

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
};

// Runs a command body: a ConfigError prints "error: file:line: key: ..." and
// gives exit code 2, any other exception exit code 1.
int withErrorExitCodes(const std::function<int()>& body);

int runRender(const RenderArgs& args);

struct RunArgs {
  std::string experiment;
  bool quick = false, resume = false, noReport = false;
  int jobs = 1;
  std::string results = "results";
};
int runExperimentCommand(const RunArgs& args);
int lightbenchMain(int argc, char** argv);
std::string versionString();

}  // namespace lb
