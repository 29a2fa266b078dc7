#include "loaded_pair.h"

#include <algorithm>
#include <chrono>

namespace shore::bench {

BusyLoad::BusyLoad(int threads) {
  for (int k = 0; k < threads; ++k)
    workers_.emplace_back([this] {
      volatile double x = 1.0;
      while (!stop_.load(std::memory_order_relaxed)) x = x * 1.0000001 + 1e-9;
    });
}

BusyLoad::~BusyLoad() {
  stop_ = true;
  for (std::thread& t : workers_) t.join();
}

int busy_load_threads() { return std::max(2, static_cast<int>(std::thread::hardware_concurrency())); }

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// Seconds per step over one slice of at least `slice_s`.
double time_slice(const std::function<void()>& step, double slice_s) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  long steps = 0;
  double elapsed = 0.0;
  do {
    step();
    ++steps;
    elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
  } while (elapsed < slice_s);
  return elapsed / static_cast<double>(steps);
}

}  // namespace

PairTiming time_alternating(const std::function<void()>& step_1, const std::function<void()>& step_2, double slice_s,
                            int slices) {
  std::vector<double> a, b, ratio;
  for (int k = 0; k < std::max(1, slices); ++k) {
    a.push_back(time_slice(step_1, slice_s));
    b.push_back(time_slice(step_2, slice_s));
    ratio.push_back(a.back() / b.back());
  }
  return {median(a), median(b), median(ratio)};
}

}  // namespace shore::bench
