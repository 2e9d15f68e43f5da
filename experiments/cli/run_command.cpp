// `lightbench run`: load and check the experiment, then hand it to the runner.
#include <iostream>
#include "experiments/cli/commands.h"
#include "experiments/runner.h"

namespace lb {

int runExperimentCommand(const RunArgs& args) {
  try {
    ExperimentOptions eo;
    eo.quick = args.quick;
    Experiment e = loadExperiment(args.experiment, eo);
    RunnerOptions ro;
    ro.resultsRoot = args.results;
    ro.resume = args.resume;
    ro.jobs = args.jobs;
    ro.report = !args.noReport;
    runExperiment(e, ro);
    return 0;
  } catch (const ConfigError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace lb
