// water_lake: shore-bench's 1 km lake with a boat (scenes::run_lake: water and coupling, one
// thread) for a given number of seconds, printing its samples: for instruction counts of the
// lake case as the benchmark runs it (callgrind), where wall times are noisy.
//
//   water_lake <seconds> [runs]
//
// With runs > 1 the lake is run that many times in one process and the last run printed
// (as in shore-bench, where the lake's tiles reuse memory freed by earlier cases instead of
// faulting fresh pages in).
#include <cstdio>
#include <cstdlib>

#include "shore/scenes/water_cases.h"

int main(int argc, char** argv) {
  shore::scenes::LakeCase c;
  c.seconds = argc > 1 ? std::atof(argv[1]) : 8.0;
  const int runs = argc > 2 ? std::atoi(argv[2]) : 1;
  shore::scenes::LakeResult r;
  for (int k = 0; k < runs; ++k) r = shore::scenes::run_lake(c);
  long long awake = 0;
  for (const shore::scenes::LakeSample& s : r.samples) {
    std::printf("t %.1f awake %lld (mean %.0f) ms %.4f ns/node %.3f\n", s.t, static_cast<long long>(s.awake_nodes),
                s.mean_awake_nodes, s.step_ms, s.mean_awake_nodes > 0 ? 1e6 * s.step_ms / s.mean_awake_nodes : 0.0);
    awake += s.awake_nodes;
  }
  std::printf("sum of sampled awake nodes %lld\n", awake);
  return 0;
}
