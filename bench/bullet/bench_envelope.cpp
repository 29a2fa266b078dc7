// Envelope rasterization versus one ray cast per column, side by side on the same columns
// (1 cm grid): wheel, sphere, box, convex hull. Each benchmark iteration runs all three
// methods once, interleaved, and reports their times and the speedup as counters.
//
//   shore_bullet_bench --benchmark_filter=EnvelopeVsRays
#include <benchmark/benchmark.h>

#include "shore/scenes/envelope_cases.h"

namespace {

void BM_EnvelopeVsRays(benchmark::State& state) {
  const auto cases = shore::scenes::standard_envelope_cases();
  const auto& c = cases.at(std::size_t(state.range(0)));
  state.SetLabel(c.name);
  double env = 0, world = 0, single = 0;
  shore::scenes::EnvelopeCaseResult last;
  for (auto _ : state) {
    last = shore::scenes::run_envelope_case(c, 0.01, 1);
    env += last.envelope_us;
    world += last.ray_world_us;
    single += last.ray_single_us;
  }
  const double n = double(state.iterations());
  state.counters["columns"] = last.columns;
  state.counters["covered"] = last.covered;
  state.counters["envelope_us"] = env / n;
  state.counters["ray_world_us"] = world / n;
  state.counters["ray_single_us"] = single / n;
  state.counters["speedup_world"] = world / env;
  state.counters["speedup_single"] = single / env;
  state.counters["ray_diff_mm"] = last.mean_abs_diff_mm;
}
BENCHMARK(BM_EnvelopeVsRays)->DenseRange(0, 3)->Unit(benchmark::kMillisecond)->MinTime(1.0);

}  // namespace
