#include "shore/scenes/water_kernel_cases.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <sstream>

#include "shore/scenes/static_shares.h"
#include "shore/water/reference_surface.h"
#include "shore/water/surface.h"

namespace shore::scenes {

using namespace water;

namespace {
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

Disturbance centre_drop(int n) { return Disturbance::point_height(0.5 * (n - 1), 0.5 * (n - 1), 3.0, 1.0); }

/// Times calls of step() until min_seconds have passed (at least 3 calls), in the steady
/// state: two calls untimed, not one. The first touches the memory and makes the workspace;
/// with threads > 1 a surface's pacer runs its first call on the team and the second on one
/// thread to measure both (shore/core/pacer.h), and that serial call, timed, was a third of
/// the 2048^2 case's 3 to 10 timed steps. Its later re-tries of the slower mode stay in.
template <class Step>
KernelThroughput time_steps(Step&& step, double min_seconds) {
  step();
  step();
  KernelThroughput t;
  const auto t0 = Clock::now();
  double elapsed = 0.0;
  do {
    step();
    ++t.steps;
    elapsed = seconds_since(t0);
  } while (elapsed < min_seconds || t.steps < 3);
  t.seconds_per_step = elapsed / static_cast<double>(t.steps);
  return t;
}
}  // namespace

water::SurfaceSettings kernel_case_settings(KernelVariant v, int n, int threads) {
  water::SurfaceSettings s;
  s.nx = s.ny = n;
  s.lattice = LatticeParameters::paper();
  s.threads = threads;
  s.sleep.enabled = false;  // the kernel over the whole grid, every substep
  s.mode = (v == KernelVariant::vertical_only || v == KernelVariant::reference_vertical) ? SurfaceMode::vertical_only
                                                                                         : SurfaceMode::full_3d;
  return s;
}

const char* kernel_variant_name(KernelVariant v) {
  switch (v) {
    case KernelVariant::fast_3d:
      return "fast_3d";
    case KernelVariant::reference_3d:
      return "reference_3d";
    case KernelVariant::vertical_only:
      return "vertical_only";
    case KernelVariant::reference_vertical:
      return "reference_vertical";
  }
  return "?";
}

double bytes_per_node_step(KernelVariant v) {
  switch (v) {
    case KernelVariant::fast_3d:
      return 65.0;
    case KernelVariant::vertical_only:
      return 33.0;
    case KernelVariant::reference_3d:
      return 49.0;
    case KernelVariant::reference_vertical:
      break;
  }
  return 17.0;
}

KernelThroughput measure_kernel_throughput(KernelVariant v, int n, int threads, double min_seconds, int tile) {
  water::SurfaceSettings s = kernel_case_settings(v, n, threads);
  if (tile > 0) s.sleep.tile = tile;
  const double dt = 0.3;
  KernelThroughput t;
  int substeps = 1;
  if (v == KernelVariant::fast_3d || v == KernelVariant::vertical_only) {
    Surface surf(s);
    surf.disturb(centre_drop(n));
    t = time_steps([&] { substeps = surf.step(dt).substeps; }, min_seconds);
  } else {
    ReferenceSurface surf(s);
    surf.disturb(centre_drop(n));
    t = time_steps([&] { surf.step(dt); }, min_seconds);
  }
  t.variant = v;
  t.n = n;
  t.threads = threads;
  t.substeps = substeps;
  t.node_steps_per_second = static_cast<double>(n) * n / t.seconds_per_step;
  return t;
}

double triad_bandwidth(std::size_t floats, int threads, double min_seconds) {
  const auto count = static_cast<long>(floats);
  std::unique_ptr<float[]> a(new float[floats]), b(new float[floats]), c(new float[floats]);
  for_static_shares(threads, count, [&](std::ptrdiff_t i0, std::ptrdiff_t i1) {
    for (std::ptrdiff_t i = i0; i < i1; ++i) {
      a[i] = 0.f;
      b[i] = 1.f;
      c[i] = 2.f;
    }
  });
  const float s = 0.5f;
  const auto triad = [&] {
    float* __restrict pa = a.get();
    const float* __restrict pb = b.get();
    const float* __restrict pc = c.get();
    for_static_shares(threads, count, [&](std::ptrdiff_t i0, std::ptrdiff_t i1) {
      for (std::ptrdiff_t i = i0; i < i1; ++i) pa[i] = pb[i] + s * pc[i];
    });
  };
  const KernelThroughput t = time_steps(triad, min_seconds);
  volatile float sink = a[floats / 2];
  (void)sink;
  return 12.0 * static_cast<double>(floats) / t.seconds_per_step;
}

double floor_node_steps_per_second(KernelVariant v, double bandwidth) { return bandwidth / bytes_per_node_step(v); }

double paper_grid_seconds_per_step(int threads, double min_seconds) {
  water::SurfaceSettings s = water::SurfaceSettings::paper();
  s.threads = threads;
  Surface surf(s);
  surf.disturb(Disturbance::point_velocity(24.5, 24.5, 2.0, 1.0));
  return time_steps([&] { surf.step(0.4); }, min_seconds).seconds_per_step;
}

KernelReport run_kernel_report(const std::vector<int>& sizes, const std::vector<int>& threads, double min_seconds) {
  KernelReport r;
  r.isa = Surface::fast_kernel_isa();
  const int max_threads = *std::max_element(threads.begin(), threads.end());
  r.bandwidth.assign(static_cast<std::size_t>(max_threads), 0.0);
  for (int t : threads)
    r.bandwidth[static_cast<std::size_t>(t - 1)] = triad_bandwidth(std::size_t{1} << 25, t, min_seconds);
  for (int n : sizes)
    for (int t : threads)
      for (KernelVariant v : {KernelVariant::fast_3d, KernelVariant::reference_3d, KernelVariant::vertical_only,
                              KernelVariant::reference_vertical})
        r.rows.push_back(measure_kernel_throughput(v, n, t, min_seconds));
  r.paper_grid_ms = 1e3 * paper_grid_seconds_per_step(1, min_seconds);
  return r;
}

std::string format_kernel_report(const KernelReport& r) {
  std::ostringstream o;
  char line[256];
  o << "water kernels (" << r.isa << "), node-steps per second; floor = triad bandwidth / bytes per node-step\n";
  for (std::size_t t = 0; t < r.bandwidth.size(); ++t)
    if (r.bandwidth[t] > 0.0) {
      std::snprintf(line, sizeof line, "triad bandwidth, %zu thread(s): %.2f GB/s\n", t + 1, r.bandwidth[t] * 1e-9);
      o << line;
    }
  std::snprintf(line, sizeof line, "%-19s %6s %3s %12s %10s %8s %9s\n", "variant", "n", "thr", "node-steps/s",
                "ms/step", "of floor", "vs ref");
  o << line;
  for (const KernelThroughput& row : r.rows) {
    const double bw = r.bandwidth[static_cast<std::size_t>(row.threads - 1)];
    const double floor = floor_node_steps_per_second(row.variant, bw);
    double speedup = 0.0;
    const KernelVariant ref =
        (row.variant == KernelVariant::vertical_only || row.variant == KernelVariant::reference_vertical)
            ? KernelVariant::reference_vertical
            : KernelVariant::reference_3d;
    for (const KernelThroughput& other : r.rows)
      if (other.variant == ref && other.n == row.n && other.threads == row.threads)
        speedup = row.node_steps_per_second / other.node_steps_per_second;
    std::snprintf(line, sizeof line, "%-19s %6d %3d %12.3e %10.4f %7.1f%% %8.2fx\n", kernel_variant_name(row.variant),
                  row.n, row.threads, row.node_steps_per_second, row.seconds_per_step * 1e3,
                  100.0 * row.node_steps_per_second / floor, speedup);
    o << line;
  }
  std::snprintf(line, sizeof line,
                "paper's 50 x 50 grid at dt 0.4, 1 thread: %.4f ms/step (paper: 4.8 ms, Pentium II 300 MHz)\n",
                r.paper_grid_ms);
  o << line;
  return o.str();
}

}  // namespace shore::scenes
