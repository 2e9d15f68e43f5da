#pragma once
// experiments/cluster.h's Cluster on MPI (MPI_COMM_WORLD). One per process,
// made in main() when lightbench runs under mpirun/srun: MPI_Init_thread at
// construction (FUNNELED: only the main thread calls MPI; rendering threads
// never do), MPI_Finalize at destruction.
#include "experiments/cluster.h"

namespace lb {

class MpiCluster : public Cluster {
 public:
  MpiCluster(int* argc, char*** argv);
  ~MpiCluster() override;
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  void send(int to, int tag, const std::string& bytes) override;
  Message receive(int from) override;
  int workersOnThisNode() const override { return workersOnNode_; }
  [[noreturn]] void abort(int code) override;

 private:
  int rank_ = 0, size_ = 1, workersOnNode_ = 0;
};

}  // namespace lb
