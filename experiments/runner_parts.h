#pragma once
// What the experiment runner (runner.cpp, rank 0) and a farm's worker
// (runner_worker.cpp, the other ranks) share: the tasks they exchange, how a
// run's result travels, and the identities both check. Internal to experiments/.
#include <filesystem>
#include <string>
#include <vector>
#include "experiments/experiment.h"
#include "experiments/reference.h"
#include "experiments/verdict/sequential.h"
#include "experiments/run_one.h"
#include "experiments/runner.h"

namespace lb::runner {

// Tasks a farm's worker is given (experiments/cluster.h), by kind.
enum TaskKind : uint64_t { ReferenceChunkTask = 1, RunTaskKind = 2 };

// Threads per run: --threads, else the cores this process may use shared
// among the runs at once (--jobs) or the workers on this node.
int threadsPerRun(const RunnerOptions& o, int sharers);
// What a resumed run must share with the one it continues: the experiment as
// read, its budget and repeats, and its references' keys.
std::string experimentHashOf(const Experiment& e, const std::vector<std::string>& referenceIds);
// What every rank must share to work on one experiment (runner_parts.cpp).
std::string jobIdentity(const Experiment& e, const std::string& experimentHash);
// Each scene's reference key, or its given file and variance file.
std::vector<std::string> referenceIdsOf(const Experiment& e);
MachineColumns thisMachine(int threads);
// decomposition.csv of a run folder: each configuration's final MSE split
// into bias² and variance over its repeats [0, targets[scene][configuration]).
void writeDecomposition(const Experiment& e, const std::filesystem::path& runDir,
                        const std::vector<Reference>& references, const RepeatTargets& targets);
// A run's log rows and images, as a worker sends them to rank 0.
std::string encodeRunResult(const std::vector<std::vector<std::string>>& rows, const RunOutcome& out);
void decodeRunResult(const std::string& bytes, std::vector<std::vector<std::string>>& rows, RunOutcome& out);

}  // namespace lb::runner
