// The `lightbench` program. Under mpirun/srun (an MPI build) every rank runs
// this same main: rank 0 the command as usual, the other ranks serve it as
// workers of a task farm (experiments/cluster.h), for the commands that
// distribute work (`run`, `render --distributed`).
#include <cstdlib>
#include "experiments/cli/commands.h"
#ifdef LIGHTBENCH_WITH_MPI
#include "experiments/mpi/mpi_cluster.h"
#endif

int main(int argc, char** argv) {
#ifdef LIGHTBENCH_WITH_MPI
  // Open MPI's launcher, or a PMI/PMIx one (srun), sets these: outside them
  // MPI is not initialised at all, so a plain run is unchanged.
  if (std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMIX_RANK") || std::getenv("PMI_SIZE")) {
    lb::MpiCluster cluster(&argc, &argv);
    if (cluster.size() > 1) {
      lb::Farm farm(cluster);
      int code = lb::lightbenchMain(argc, argv, &farm);
      // Rank 0 tells idle workers to exit with its code; a worker still busy
      // (rank 0 failed mid-run) cannot be told, so the job is aborted.
      if (!farm.isWorker() && !farm.stopWorkers(code)) cluster.abort(code);
      return code;
    }
  }
#endif
  return lb::lightbenchMain(argc, argv, nullptr);
}
