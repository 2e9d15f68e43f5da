#pragma once
// Runs an experiment: for each scene its reference, then every configuration ×
// repeat within the budget, recording a CSV row at each snapshot; then the
// images, meta.json and (through experiments/report.py) plots and the report.
#include <string>
#include "experiments/experiment.h"

namespace lb {

struct RunnerOptions {
  std::string resultsRoot = "results";
  bool resume = false;   // continue the latest run of this experiment
  int jobs = 1;          // runs at once, each with cores/jobs threads
  bool report = true;    // call report.py at the end
  std::string python;    // its interpreter ("" : reportInterpreter's default)
};

// Returns the run folder, results/<name>/<run-id>/.
std::string runExperiment(const Experiment& experiment, const RunnerOptions& options);

// Columns of log.csv, in order.
extern const char* const LogColumns[];

}  // namespace lb
