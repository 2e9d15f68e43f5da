#include "integrators/bidirectional/cost_split.h"
#include <atomic>
#include <chrono>
#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#endif

namespace lb::bidir {

namespace {

using Clock = std::chrono::steady_clock;

// The time-stamp counter where there is one (constant-rate on every x86 CPU
// of the last fifteen years), else the steady clock in nanoseconds.
uint64_t ticks() {
#if defined(__x86_64__) || defined(__i386__)
  return __rdtsc();
#else
  return uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count());
#endif
}

std::atomic<bool> on{false};
std::array<std::atomic<uint64_t>, PhaseCount> totals{};
std::array<std::atomic<double>, PhaseCount> charged{};
// The clock pair converting ticks to seconds, taken when switched on.
uint64_t ticks0 = 0;
Clock::time_point time0;

struct ThreadCost {
  Phase current = Phase::None;
  uint64_t since = 0;
  std::array<uint64_t, PhaseCount> ticks{};
};
thread_local ThreadCost cost;

}  // namespace

const char* phaseName(Phase p) {
  static const char* names[PhaseCount] = {"none", "light", "index", "camera", "connections", "merges", "weights"};
  return names[int(p)];
}

void CostSplit::enable(bool enable) {
  if (enable) reset();
  on.store(enable, std::memory_order_relaxed);
}

bool CostSplit::enabled() { return on.load(std::memory_order_relaxed); }

void CostSplit::reset() {
  for (auto& t : totals) t.store(0);
  for (auto& c : charged) c.store(0);
  ticks0 = ticks();
  time0 = Clock::now();
}

std::array<double, PhaseCount> CostSplit::threadSeconds() {
  double seconds = std::chrono::duration<double>(Clock::now() - time0).count();
  double elapsedTicks = double(ticks() - ticks0);
  double secondsPerTick = elapsedTicks > 0 ? seconds / elapsedTicks : 0;
  std::array<double, PhaseCount> s{};
  for (int p = 1; p < PhaseCount; ++p) s[size_t(p)] = double(totals[size_t(p)].load()) * secondsPerTick + charged[size_t(p)].load();
  return s;
}

void CostSplit::charge(Phase p, double threadSeconds) {
  if (!enabled()) return;
  auto& c = charged[size_t(p)];
  double old = c.load();
  while (!c.compare_exchange_weak(old, old + threadSeconds)) {
  }
}

PhaseScope::PhaseScope(Phase phase) {
  if (!CostSplit::enabled()) return;
  active_ = true;
  uint64_t now = ticks();
  cost.ticks[size_t(cost.current)] += now - cost.since;
  previous_ = cost.current;
  cost.current = phase;
  cost.since = now;
}

PhaseScope::~PhaseScope() {
  if (!active_) return;
  uint64_t now = ticks();
  cost.ticks[size_t(cost.current)] += now - cost.since;
  cost.current = previous_;
  cost.since = now;
  if (cost.current != Phase::None) return;
  for (int p = 1; p < PhaseCount; ++p)
    if (cost.ticks[size_t(p)]) totals[size_t(p)].fetch_add(cost.ticks[size_t(p)], std::memory_order_relaxed), cost.ticks[size_t(p)] = 0;
  cost.ticks[0] = 0;
}

}  // namespace lb::bidir
