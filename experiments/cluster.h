#pragma once
// The processes of a distributed run (issue 19), as experiments/ sees them:
// numbered ranks that send each other byte strings. The implementation is
// MPI's (experiments/mpi/mpi_cluster.cpp, in an -DLIGHTBENCH_MPI=ON build,
// linked into the executable only); nothing here depends on MPI.
//
// On top of it, a task farm ("self-scheduling", master and workers): rank 0
// only coordinates and hands out one task at a time to whichever worker asks,
// so fast and slow ranks stay busy until the queue is empty, and a task's
// result comes back to rank 0, which alone writes files.
//
// Faults: MPI (the standard, and Debian's Open MPI 4.1, which has no ULFM
// extension) gives no way to survive a dead rank: the job ends. So a farm
// never holds results only in memory for long: rank 0 writes each finished
// task's result at once, and a rerun with --resume redoes only what is
// missing (experiments/runner.h).
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>
#include "core/image.h"

namespace lb {

struct Message {
  int source = -1, tag = 0;
  std::string bytes;
};

class Cluster {
 public:
  static constexpr int AnySource = -1;
  virtual ~Cluster() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  virtual void send(int to, int tag, const std::string& bytes) = 0;
  // The next message from `from` (or any rank). Waiting sleeps between
  // probes: MPI's blocking receive spins, and an idle rank 0 would take a
  // core from the rank rendering beside it.
  virtual Message receive(int from) = 0;
  // Ranks other than 0 on this rank's node: they share its cores.
  virtual int workersOnThisNode() const = 0;
  // Ends every rank at once (MPI_Abort): for a failure while workers are busy.
  [[noreturn]] virtual void abort(int code) = 0;
};

// Threads for a worker rank's render: `requested` if positive, else the
// cores it may use (its affinity: mpirun's binding), but no more than its
// share of the node's cores among the node's worker ranks.
int workerThreads(int requested, const Cluster& cluster);

// A worker's task that threw: its exit code (2 for bad input) and message,
// rethrown on rank 0 so the command fails as a single process would.
struct RemoteFailure : std::runtime_error {
  RemoteFailure(int code, const std::string& message) : std::runtime_error(message), exitCode(code) {}
  int exitCode;
};

class Farm {
 public:
  explicit Farm(Cluster& cluster) : cluster_(cluster) {}
  Cluster& cluster() { return cluster_; }
  bool isWorker() const { return cluster_.rank() != 0; }
  int workers() const { return cluster_.size() - 1; }

  // Rank 0: hands out the tasks `next(worker)` yields (until it yields
  // nothing) to idle workers, and gives every result to `onResult` as it arrives, in
  // arrival order; returns when all handed-out tasks are back. A worker's
  // failure is thrown as a RemoteFailure.
  void distribute(const std::function<std::optional<std::string>(int worker)>& next,
                  const std::function<void(int worker, std::string&& result)>& onResult);
  // Rank 0, at the end: every worker is told to exit with `code`. False if a
  // worker is still busy with a task (the caller then aborts the job).
  bool stopWorkers(int code);

  // A worker: asks for tasks and answers each with work(task) until rank 0
  // says stop; returns the exit code rank 0 sent. An exception thrown by
  // `work` is reported to rank 0, which ends the job.
  int serve(const std::function<std::string(const std::string& task)>& work);

 private:
  Cluster& cluster_;
  std::vector<int> idle_;  // workers waiting for a task
  int busy_ = 0;
  bool stopped_ = false;
};

// Tasks and results as bytes: numbers, strings and images appended in order
// and read back in the same order (the same program on every rank).
class ByteWriter {
 public:
  ByteWriter& u64(uint64_t v) { return raw(&v, sizeof v); }
  ByteWriter& f64(double v) { return raw(&v, sizeof v); }
  ByteWriter& str(const std::string& s) { return u64(s.size()).raw(s.data(), s.size()); }
  ByteWriter& image(const Image& img);
  std::string take() { return std::move(bytes_); }

 private:
  ByteWriter& raw(const void* p, size_t n) {
    bytes_.append(static_cast<const char*>(p), n);
    return *this;
  }
  std::string bytes_;
};

class ByteReader {
 public:
  explicit ByteReader(const std::string& bytes) : bytes_(bytes) {}
  uint64_t u64() { return read<uint64_t>(); }
  double f64() { return read<double>(); }
  std::string str();
  Image image();

 private:
  template <typename T>
  T read() {
    T v;
    raw(&v, sizeof v);
    return v;
  }
  void raw(void* p, size_t n);
  const std::string& bytes_;
  size_t at_ = 0;
};

}  // namespace lb
