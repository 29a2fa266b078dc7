#pragma once
// Whether forking onto a Team pays, decided call by call from measured times. On a loaded
// machine a worker may be descheduled while it holds an item and the caller then waits for
// it, so parallel calls can be slower than serial ones whatever the work threshold says. The
// pacer keeps an average time per unit of work for each mode, runs the faster one, and
// re-tries the slower one at intervals that double each time it loses again (16 calls up to
// 4096). The choice changes only speed: every caller's results are the same on any thread
// count.

namespace shore {

struct Pacer {
  double serial = -1.0;  ///< s per unit of work, exponential average; < 0: not measured yet
  double parallel = -1.0;
  int interval = 16;  ///< calls between tries of the slower mode
  int countdown = 0;

  /// Whether the next call should fork (measures parallel first, then serial).
  [[nodiscard]] bool choose_parallel();
  /// Records the time per unit of work of a call that ran parallel or not.
  void record(bool parallel_run, double seconds_per_unit);
};

}  // namespace shore
