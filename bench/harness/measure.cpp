#include "measure.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <numeric>
#include <vector>

#include "shore/scenes/static_shares.h"

namespace shore::bench {

Measurement measure(const std::function<void()>& fn, double min_seconds, int min_repeats) {
  using Clock = std::chrono::steady_clock;
  fn();  // warm-up: caches, page faults, lazy allocations
  std::vector<double> times;
  double total = 0.0;
  while (total < min_seconds || static_cast<int>(times.size()) < min_repeats) {
    const auto t0 = Clock::now();
    fn();
    const double t = std::chrono::duration<double>(Clock::now() - t0).count();
    times.push_back(t);
    total += t;
    if (times.size() > 100000) break;  // a call that takes no time at all
  }
  Measurement m;
  m.repeats = static_cast<int>(times.size());
  m.mean_s = total / m.repeats;
  std::sort(times.begin(), times.end());
  m.min_s = times.front();
  const std::size_t mid = times.size() / 2;
  m.median_s = times.size() % 2 ? times[mid] : 0.5 * (times[mid - 1] + times[mid]);
  return m;
}

TriadResult triad_bandwidth(std::size_t n, int threads, double min_seconds) {
  // Raw arrays, not std::vector: the first touch must happen in the parallel loop so that
  // pages land where the threads that use them run.
  std::unique_ptr<double[]> a(new double[n]), b(new double[n]), c(new double[n]);
  const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(n);
  scenes::for_static_shares(threads, count, [&](std::ptrdiff_t i0, std::ptrdiff_t i1) {
    for (std::ptrdiff_t i = i0; i < i1; ++i) {
      a[i] = 0.0;
      b[i] = 1.0;
      c[i] = 2.0;
    }
  });
  const double s = 3.0;
  double* pa = a.get();
  const double* pb = b.get();
  const double* pc = c.get();
  const Measurement m = measure(
      [&] {
        scenes::for_static_shares(threads, count, [&](std::ptrdiff_t i0, std::ptrdiff_t i1) {
          for (std::ptrdiff_t i = i0; i < i1; ++i) pa[i] = pb[i] + s * pc[i];
        });
      },
      min_seconds, 5);
  TriadResult r;
  r.elements = n;
  r.threads = threads;
  r.gbps = 24.0 * static_cast<double>(n) / m.median_s / 1e9;
  // Keep the result observable so the loop cannot be dropped.
  if (pa[n / 2] != 7.0) r.gbps = -1.0;
  return r;
}

std::size_t triad_elements_for_this_machine() {
  long llc = sysconf(_SC_LEVEL3_CACHE_SIZE);
  if (llc <= 0) llc = sysconf(_SC_LEVEL2_CACHE_SIZE);
  if (llc <= 0) llc = 32L << 20;
  const std::size_t per_array = std::max<std::size_t>(64u << 20, static_cast<std::size_t>(llc) * 4 / 3);
  return per_array / sizeof(double);
}

}  // namespace shore::bench
