// shore_terrain_bench: time per Terrain::step for a boot footprint, a rolling wheel and a
// towed wheel at 1 cm in dry sand, 1 and 2 threads (regions this small run on one thread unless
// parallel_min_columns is lowered: the "split" rows force it).
#include <benchmark/benchmark.h>

#include "shore/scenes/terrain_step_cases.h"

namespace {

using shore::scenes::TerrainCase;

void BM_TerrainStep(benchmark::State& state) {
  const auto c = static_cast<TerrainCase>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const bool split = state.range(2) != 0;
  shore::scenes::TerrainCaseResult r;
  for (auto _ : state) {
    r = shore::scenes::run_terrain_case(c, threads, c == TerrainCase::towed_wheel ? 100 : 400, split);
    state.SetIterationTime(r.ms_per_step * 1e-3);
  }
  state.SetLabel(std::string(r.name) + (split ? " split" : ""));
  state.counters["active_columns"] = r.active_columns;
  state.counters["erosion_passes"] = r.erosion_passes;
  state.counters["columns_per_s"] = r.columns_per_second;
  state.counters["bearing_ms"] = r.bearing_ms_per_step;
  state.counters["threads"] = threads;
}

}  // namespace

// Args: case (0 footprint, 1 wheel, 2 towed wheel), threads, split small regions between threads.
BENCHMARK(BM_TerrainStep)
    ->Args({0, 1, 0})
    ->Args({0, 2, 0})
    ->Args({0, 2, 1})
    ->Args({1, 1, 0})
    ->Args({1, 2, 0})
    ->Args({1, 2, 1})
    ->Args({2, 1, 0})
    ->Args({2, 2, 0})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

BENCHMARK_MAIN();
