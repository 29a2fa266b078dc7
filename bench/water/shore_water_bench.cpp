// shore_water_bench: Google Benchmark cases for the water kernels, with the memory floor
// (STREAM-style triad) measured in the same run. `--report` prints the summary table
// (speed-ups against the reference kernel and the fraction of the floor) instead.

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "shore/scenes/water_kernel_cases.h"
#include "shore/water/reference_surface.h"
#include "shore/water/surface.h"

using namespace shore::water;
using namespace shore::scenes;

namespace {

std::vector<double> g_bandwidth(3, 0.0);  // bytes/s by threads

void set_counters(benchmark::State& state, KernelVariant v, int n, int threads) {
  const double nodes = static_cast<double>(n) * n * static_cast<double>(state.iterations());
  state.counters["node_steps/s"] = benchmark::Counter(nodes, benchmark::Counter::kIsRate);
  // Time the floor would take over the time taken: the fraction of the memory floor reached.
  const double floor_seconds = nodes * bytes_per_node_step(v) / g_bandwidth[static_cast<std::size_t>(threads)];
  state.counters["of_floor"] = benchmark::Counter(floor_seconds, benchmark::Counter::kIsRate);
}

void bm_surface(benchmark::State& state, KernelVariant v) {
  const int n = static_cast<int>(state.range(0)), threads = static_cast<int>(state.range(1));
  Surface surf(kernel_case_settings(v, n, threads));
  surf.disturb(Disturbance::point_height(0.5 * (n - 1), 0.5 * (n - 1), 3.0, 1.0));
  for (auto _ : state) benchmark::DoNotOptimize(surf.step(0.3));
  set_counters(state, v, n, threads);
}

void bm_reference(benchmark::State& state, KernelVariant v) {
  const int n = static_cast<int>(state.range(0)), threads = static_cast<int>(state.range(1));
  ReferenceSurface surf(kernel_case_settings(v, n, 1));
  surf.disturb(Disturbance::point_height(0.5 * (n - 1), 0.5 * (n - 1), 3.0, 1.0));
  for (auto _ : state) surf.step(0.3);
  set_counters(state, v, n, threads);
}

void bm_triad(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  double bw = 0.0;
  for (auto _ : state) bw = triad_bandwidth(std::size_t{1} << 25, threads, 0.2);
  state.counters["GB/s"] = bw * 1e-9;
}

void bm_paper_grid(benchmark::State& state) {
  SurfaceSettings s = SurfaceSettings::paper();
  s.threads = 1;
  Surface surf(s);
  surf.disturb(Disturbance::point_velocity(24.5, 24.5, 2.0, 1.0));
  for (auto _ : state) benchmark::DoNotOptimize(surf.step(0.4));
}

void register_all() {
  const auto sizes = {64, 256, 1024, 2048};
  for (int threads : {1, 2}) {
    for (int n : sizes) {
      const auto args = std::vector<int64_t>{n, threads};
      benchmark::RegisterBenchmark("fast_3d", bm_surface, KernelVariant::fast_3d)->Args(args)->UseRealTime();
      benchmark::RegisterBenchmark("vertical_only", bm_surface, KernelVariant::vertical_only)
          ->Args(args)
          ->UseRealTime();
      if (threads == 1) {
        benchmark::RegisterBenchmark("reference_3d", bm_reference, KernelVariant::reference_3d)
            ->Args(args)
            ->UseRealTime();
        benchmark::RegisterBenchmark("reference_vertical", bm_reference, KernelVariant::reference_vertical)
            ->Args(args)
            ->UseRealTime();
      }
    }
  }
  benchmark::RegisterBenchmark("triad", bm_triad)->Arg(1)->Arg(2)->Iterations(1)->UseRealTime();
  benchmark::RegisterBenchmark("paper_50x50_dt0.4", bm_paper_grid)->UseRealTime()->Unit(benchmark::kMillisecond);
}

}  // namespace

int main(int argc, char** argv) {
  bool report = false;
  std::vector<char*> rest;
  for (int i = 0; i < argc; ++i) {
    if (std::strcmp(argv[i], "--report") == 0) {
      report = true;
    } else {
      rest.push_back(argv[i]);
    }
  }
  if (report) {
    const KernelReport r = run_kernel_report({64, 256, 1024, 2048}, {1, 2}, 0.5);
    std::fputs(format_kernel_report(r).c_str(), stdout);
    return 0;
  }
  for (int t = 1; t <= 2; ++t) g_bandwidth[static_cast<std::size_t>(t)] = triad_bandwidth(std::size_t{1} << 25, t, 0.3);
  std::printf("triad bandwidth: %.2f GB/s (1 thread), %.2f GB/s (2 threads); fast kernel ISA: %s\n",
              g_bandwidth[1] * 1e-9, g_bandwidth[2] * 1e-9, Surface::fast_kernel_isa());
  int n = static_cast<int>(rest.size());
  benchmark::Initialize(&n, rest.data());
  register_all();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
