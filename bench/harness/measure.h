#pragma once
// Timing and machine baselines for shore-bench.

#include <cstddef>
#include <functional>

namespace shore::bench {

struct Measurement {
  double median_s = 0.0;  ///< median wall time of one call, s
  double min_s = 0.0;     ///< fastest call, s
  double mean_s = 0.0;    ///< mean call, s
  int repeats = 0;        ///< calls timed
};

/// Calls fn repeatedly (after one untimed warm-up call) until at least min_seconds of timed
/// calls and min_repeats calls; returns the median (robust to a noisy, shared machine).
Measurement measure(const std::function<void()>& fn, double min_seconds = 0.2, int min_repeats = 5);

struct TriadResult {
  double gbps = 0.0;         ///< 24 bytes per element / median time (STREAM's counting), GB/s
  std::size_t elements = 0;  ///< doubles per array
  int threads = 0;
};

/// STREAM-style triad a[i] = b[i] + s * c[i] over three arrays of `elements` doubles with
/// `threads` threads (scenes::for_static_shares: first touch by the same threads and schedule).
TriadResult triad_bandwidth(std::size_t elements, int threads, double min_seconds = 0.3);

/// Elements per array so that the three arrays together are about 4x the last-level
/// cache (at least 3 x 64 MB).
std::size_t triad_elements_for_this_machine();

}  // namespace shore::bench
