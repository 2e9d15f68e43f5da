#pragma once
// A progress line for work that is not rendering passes: photon tracing, the
// irradiance cache's prepass, reference chunks. "photon tracing [ 42%] ETA 3.1 s",
// redrawn in place on a terminal (at most 4 times a second), a line every 5 s
// otherwise, closed by finish()'s 100 % line. Thread-safe: workers call
// advance() from any thread.
#include <atomic>
#include <chrono>
#include <mutex>
#include <string>

namespace lb {

class Progress {
 public:
  // Disabled (prints nothing) when !enabled: callers need no branches.
  Progress(std::string what, double total, bool enabled);
  ~Progress();  // prints nothing: the 100 % line is finish()'s
  void advance(double amount);
  void finish();

 private:
  void print(double done, bool last);
  std::string what_;
  double total_;
  bool enabled_, tty_, finished_ = false;
  std::atomic<double> done_{0};
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_;
  double lastPrint_ = -1;
};

}  // namespace lb
