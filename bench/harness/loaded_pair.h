#pragma once
// 1 thread against 2 on a loaded machine, shared by the water's and the soil's thread
// sweeps: busy threads load every core while the two set-ups step in short alternating
// slices, and the speed-up is the median of the ratio of adjacent slices (robust to the
// load's bursts; the medians of the times alone are not).

#include <atomic>
#include <functional>
#include <thread>
#include <vector>

namespace shore::bench {

/// Busy threads that load every core while alive.
class BusyLoad {
 public:
  explicit BusyLoad(int threads);
  ~BusyLoad();
  BusyLoad(const BusyLoad&) = delete;
  BusyLoad& operator=(const BusyLoad&) = delete;

 private:
  std::atomic<bool> stop_{false};
  std::vector<std::thread> workers_;
};

/// How many busy threads load this machine: its hardware threads, at least 2.
int busy_load_threads();

struct PairTiming {
  double s_per_step_1 = 0.0;  ///< median over slices, s
  double s_per_step_2 = 0.0;
  double speed_2_over_1 = 0.0;  ///< median of (slice time per step of 1) / (of 2), adjacent slices
};

/// Alternates `slices` slices of at least `slice_s` seconds of step_1() and step_2(); each
/// call is one step.
PairTiming time_alternating(const std::function<void()>& step_1, const std::function<void()>& step_2, double slice_s,
                            int slices);

}  // namespace shore::bench
