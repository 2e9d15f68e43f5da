// `lightbench run`: load and check the experiment, then hand it to the runner.
#include <iostream>
#include "experiments/cli/commands.h"
#include "core/error.h"
#include "experiments/cli/flag_checks.h"
#include "experiments/runner.h"

namespace lb {

int runExperimentCommand(const RunArgs& args) {
  return withErrorExitCodes([&] {
    ExperimentOptions eo;
    eo.quick = args.quick;
    Experiment e = loadExperiment(args.experiment, eo);
    // Before any reference renders: the results folder (created if missing).
    checkWritableFolder("--results", args.results);
    RunnerOptions ro;
    ro.resultsRoot = args.results;
    ro.resume = args.resume;
    ro.jobs = args.jobs;
    ro.report = !args.noReport;
    runExperiment(e, ro);
    return 0;
  });
}

}  // namespace lb
