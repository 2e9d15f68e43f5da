#include "core/progress.h"
#include <unistd.h>
#include <algorithm>
#include <cstdio>
#include "core/format.h"

namespace lb {

Progress::Progress(std::string what, double total, bool enabled)
    : what_(std::move(what)), total_(total), enabled_(enabled && total > 0), tty_(isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()) {}

// Not finish(): while unwinding from an exception a "100 %" line would be false.
Progress::~Progress() = default;

void Progress::advance(double amount) {
  if (!enabled_) return;
  double done = done_.load();
  while (!done_.compare_exchange_weak(done, done + amount)) {
  }
  done += amount;
  double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);  // a busy printer skips, never waits
  if (!lock || t - lastPrint_ < (tty_ ? 0.25 : 5.0)) return;
  lastPrint_ = t;
  print(done, false);
}

void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  print(total_, true);
}

void Progress::print(double done, bool last) {
  double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  double fraction = std::clamp(done / total_, 0.0, 1.0);
  std::string tail = last ? "done in " + formatSeconds(t)
                          : "ETA " + (fraction > 0 ? formatSeconds(t / fraction - t) : std::string("?"));
  std::fprintf(stderr, "%s%s [%3d%%] %s%s", tty_ ? "\r" : "", what_.c_str(), int(100 * fraction), tail.c_str(),
               tty_ && !last ? "   " : "\n");
  std::fflush(stderr);
}

}  // namespace lb
