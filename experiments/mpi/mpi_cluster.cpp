#include "experiments/mpi/mpi_cluster.h"
#include <mpi.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <thread>

namespace lb {

MpiCluster::MpiCluster(int* argc, char*** argv) {
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  // Rendering threads never call MPI, but an MPI that cannot even promise
  // that is one we must not run on.
  if (provided < MPI_THREAD_FUNNELED) {
    if (rank_ == 0) std::fprintf(stderr, "error: this MPI does not support threads (MPI_THREAD_FUNNELED)\n");
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  // The ranks sharing this node's memory (and cores): MPI-3's shared-memory
  // split. Rank 0 coordinates and does not count.
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  int isWorker = rank_ != 0;
  MPI_Allreduce(&isWorker, &workersOnNode_, 1, MPI_INT, MPI_SUM, node);
  MPI_Comm_free(&node);
}

MpiCluster::~MpiCluster() { MPI_Finalize(); }

void MpiCluster::send(int to, int tag, const std::string& bytes) {
  if (bytes.size() > size_t(INT32_MAX)) throw std::runtime_error("a message of more than 2 GiB between ranks");
  MPI_Send(bytes.data(), int(bytes.size()), MPI_BYTE, to, tag, MPI_COMM_WORLD);
}

Message MpiCluster::receive(int from) {
  MPI_Status status;
  int flag = 0;
  // Probe, then sleep for a growing while (50 µs up to 2 ms): a message waits
  // at most 2 ms, and a waiting rank uses no core.
  for (int sleepUs = 50;; sleepUs = std::min(2 * sleepUs, 2000)) {
    MPI_Iprobe(from == AnySource ? MPI_ANY_SOURCE : from, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
    if (flag) break;
    std::this_thread::sleep_for(std::chrono::microseconds(sleepUs));
  }
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  Message m;
  m.source = status.MPI_SOURCE;
  m.tag = status.MPI_TAG;
  m.bytes.resize(size_t(count));
  MPI_Recv(m.bytes.data(), count, MPI_BYTE, m.source, m.tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return m;
}

void MpiCluster::abort(int code) {
  std::fflush(stderr);
  MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);  // not reached
}

}  // namespace lb
