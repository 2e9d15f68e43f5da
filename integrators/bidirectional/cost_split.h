#pragma once
// Where a bidirectional iteration spends its time (the benchmark's cost
// split, issue 33): light subpaths, the merging index, camera subpaths,
// connections, merges and MIS weights, each exclusive of the others (a
// connection's weight is charged to Weights, not to Connections).
//
// Off unless a benchmark turns it on. Then each change of phase reads the
// CPU's time-stamp counter (some 10 ns), small beside a connection (a shadow
// ray and two BSDF evaluations, a few hundred ns), but not nothing: the
// split's own benchmark rows say how much slower they ran. Off, a phase
// costs one load and a branch.
#include <array>
#include <cstdint>

namespace lb::bidir {

enum class Phase : int { None, LightSubpaths, Index, CameraSubpaths, Connections, Merges, Weights, Count };
constexpr int PhaseCount = int(Phase::Count);
const char* phaseName(Phase p);  // "light", "index", "camera", "connections", "merges", "weights"

class CostSplit {
 public:
  // Turning it on starts the clock that converts ticks to seconds.
  static void enable(bool on);
  static bool enabled();
  static void reset();
  // Thread-seconds spent in each phase since enable(true) or reset(),
  // summed over threads (indexed by Phase; None holds nothing).
  static std::array<double, PhaseCount> threadSeconds();
  // For work timed from outside, such as a parallel index build: its wall
  // time times the threads it occupied.
  static void charge(Phase p, double threadSeconds);
};

// Charges the time from its construction to its destruction to `phase`, and
// the time before it to the phase it interrupts. A thread's ticks reach the
// totals when its outermost scope ends, so a renderer opens one per pixel.
class PhaseScope {
 public:
  explicit PhaseScope(Phase phase);
  ~PhaseScope();
  PhaseScope(const PhaseScope&) = delete;
  PhaseScope& operator=(const PhaseScope&) = delete;

 private:
  Phase previous_ = Phase::None;
  bool active_ = false;
};

}  // namespace lb::bidir
