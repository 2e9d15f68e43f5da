#pragma once
// Runs an experiment: for each scene its reference, then every configuration ×
// repeat within the budget, recording a CSV row at each snapshot; then the
// images, meta.json and (through experiments/report.py) plots and the report.
#include <string>
#include "experiments/cluster.h"
#include "experiments/experiment.h"
#include "experiments/run_log.h"  // LogColumns

namespace lb {

struct RunnerOptions {
  std::string resultsRoot = "results";
  bool resume = false;   // continue the latest run of this experiment
  int jobs = 1;          // runs at once, each with cores/jobs threads
  bool report = true;    // call report.py at the end
  std::string python;    // its interpreter ("" : reportInterpreter's default)
  int threads = 0;       // per run; 0: the cores shared among the runs at once (or a node's worker ranks)
  bool mixedMachines = false;  // let the report compare runs timed on different kinds of machines
  // Under MPI (issue 19): rank 0 runs the experiment with the farm's workers
  // rendering its reference chunks and runs; nullptr or no workers: here.
  Farm* farm = nullptr;
};

// Returns the run folder, results/<name>/<run-id>/.
std::string runExperiment(const Experiment& experiment, const RunnerOptions& options);

// A worker rank's side of runExperiment: renders the reference chunks and
// runs rank 0 hands out until it says stop; returns rank 0's exit code.
int serveExperiment(const std::string& experimentFile, const ExperimentOptions& eo, const RunnerOptions& o);

}  // namespace lb
