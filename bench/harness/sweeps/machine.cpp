// machine: the memory floor. A STREAM-style triad measures the bandwidth this machine
// gives 1 and 2 threads, in the same run as the other sweeps, so grid kernels (water,
// soil) can be reported as a fraction of it.
#include <cstdio>

#include "measure.h"
#include "sweep.h"

namespace shore::bench {
namespace {

void run(const SweepContext& ctx, SweepResult& out) {
  const std::size_t n = triad_elements_for_this_machine();
  const double min_seconds = ctx.quick ? 0.3 : 1.5;
  Table& t = out.table("machine_triad", {"threads", "array_mb", "triad_gbps"});
  double gbps[3] = {0, 0, 0};
  for (int threads : {1, 2}) {
    ctx.progress("triad, " + std::to_string(threads) + " thread(s), 3 arrays of " +
                 std::to_string(n * sizeof(double) >> 20) + " MB");
    const TriadResult r = triad_bandwidth(n, threads, min_seconds);
    gbps[threads] = r.gbps;
    t.add({static_cast<double>(threads), static_cast<double>(n * sizeof(double)) / (1 << 20), r.gbps});
  }
  out.figure("machine.triad_gbps_1t", gbps[1], "GB/s");
  out.figure("machine.triad_gbps_2t", gbps[2], "GB/s");
  char note[200];
  std::snprintf(note, sizeof note,
                "STREAM-style triad a = b + s c over three arrays of %zu MB each (about 4x the last-level cache), "
                "24 bytes counted per element, median of repeated passes.",
                n * sizeof(double) >> 20);
  out.note(note);
}

const SweepRegistrar kRegistered{Sweep{
    .name = "machine",
    .description = "memory bandwidth floor: STREAM-style triad, 1 and 2 threads",
    .run = run,
}};

}  // namespace
}  // namespace shore::bench
