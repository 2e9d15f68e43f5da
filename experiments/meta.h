#pragma once
// meta.json of a run: what is needed to repeat it — git commit, machine,
// threads, seeds, the fully resolved configuration, library versions.
#include <map>
#include <string>
#include "experiments/experiment.h"

namespace lb {

struct RunMeta {
  std::string started;
  int threadsPerRun = 0, jobs = 1, ranks = 1;
  std::map<std::string, std::string> referenceKeys;
  std::map<std::string, std::string> referenceUsed;  // the reference as used: chunks, spp, seconds
  std::map<std::string, double> referenceRmseFloor;  // sqrt of the reference's mean variance
  std::map<std::string, uint64_t> referenceChunks;   // chunks of a rendered reference (0: a given EXR)
  std::string experimentHash;  // what --resume checks: the same experiment, budget and references
};

RunMeta startMeta(const Experiment& e, const std::string& runDir, int threadsPerRun, int jobs,
                  const std::string& experimentHash);
// meta.json again: after the references are known (or extended), and once finished.
void writeMeta(const RunMeta& meta, const Experiment& e, const std::string& runDir, bool finished);
// This machine, as meta.json and the log's host and cpu columns name it.
std::string hostName();
std::string cpuModel();
// The experiment_hash of a run folder's meta.json ("" if it has none or the
// file is not JSON): what --resume compares.
std::string readExperimentHash(const std::string& runDir);

}  // namespace lb
