#include <benchmark/benchmark.h>

#include "shore/terrain/bekker.h"

static void BM_StaticWheelSinkage(benchmark::State& state) {
  const auto sand = shore::terrain::Material::sand();
  for (auto _ : state) benchmark::DoNotOptimize(shore::terrain::bekker::wheel_sinkage_static(sand, 4000, 0.8, 0.3));
}
BENCHMARK(BM_StaticWheelSinkage);
