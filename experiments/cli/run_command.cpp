// `lightbench run`: load and check the experiment, then hand it to the runner.
#include <filesystem>
#include <iostream>
#include "core/params.h"
#include "experiments/cli/commands.h"
#include "core/error.h"
#include "experiments/cli/flag_checks.h"
#include "experiments/runner.h"

namespace lb {

int runExperimentCommand(const RunArgs& args) {
  return withErrorExitCodes([&] {
    ExperimentOptions eo;
    eo.quick = args.quick;
    // `lightbench run scene.yaml`: say which command was meant.
    bool scene = std::filesystem::path(args.experiment).extension() == ".xml";
    if (!scene) {
      YAML::Node root = loadYamlFile(args.experiment);
      scene = root.IsMap() && !root["configurations"] && (root["camera"] || root["shapes"]);
    }
    if (scene)
      throw ConfigError(args.experiment, 0, "", "this is a scene, not an experiment: render it with 'lightbench render " +
                                                    args.experiment + "'");
    if (args.farm && args.jobs > 1)
      throw ConfigError(args.experiment, 0, "--jobs", "under MPI each rank runs one run at a time; start more ranks instead");
    Experiment e = loadExperiment(args.experiment, eo);
    // Before any reference renders: the results folder (created if missing).
    checkWritableFolder("--results", args.results);
    RunnerOptions ro;
    ro.resultsRoot = args.results;
    ro.resume = args.resume;
    ro.jobs = args.jobs;
    ro.report = !args.noReport;
    ro.python = args.python;
    ro.threads = args.threads;
    ro.mixedMachines = args.mixedMachines;
    ro.farm = args.farm;
    runExperiment(e, ro);
    return 0;
  });
}

int serveExperimentCommand(const RunArgs& args) {
  return withErrorExitCodes([&] {
    ExperimentOptions eo;
    eo.quick = args.quick;
    RunnerOptions ro;
    ro.resultsRoot = args.results;
    ro.threads = args.threads;
    ro.farm = args.farm;
    return serveExperiment(args.experiment, eo, ro);
  });
}

}  // namespace lb
