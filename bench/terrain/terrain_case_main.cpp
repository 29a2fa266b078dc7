// shore_terrain_case: runs one terrain case once and prints its numbers, for quick
// before/after comparisons and for callgrind (one run, no benchmark repetitions).
//   shore_terrain_case towed_wheel [cell_m] [threads] [steps] [sinkage_m] [star 0|1]
//   shore_terrain_case footprint|wheel [threads] [steps]
#include <cstdio>
#include <cstdlib>
#include <string>

#include "shore/scenes/terrain_step_cases.h"

namespace tb = shore::scenes;

namespace {

void print(const tb::TerrainCaseResult& r, double cell) {
  std::printf(
      "%s cell %.3f m threads %d: %.4f ms/step (last %d steps), bearing %.4f ms, active columns %.0f, "
      "erosion passes %.2f, hash %016llx, volume error %.3e m^3, bearing sum %.17g\n",
      r.name.c_str(), cell, r.threads, r.ms_per_step, r.steps, r.bearing_ms_per_step, r.active_columns,
      r.erosion_passes, static_cast<unsigned long long>(r.state_hash), r.volume_error, r.bearing_sum);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string which = argc > 1 ? argv[1] : "towed_wheel";
  if (which == "towed_wheel") {
    tb::TowedWheelCase c;
    if (argc > 2) c.cell = std::atof(argv[2]);
    if (argc > 3) c.threads = std::atoi(argv[3]);
    if (argc > 4) c.steps = std::atoi(argv[4]);
    if (argc > 5) c.sinkage = std::atof(argv[5]);
    if (argc > 6) c.star = std::atoi(argv[6]) != 0;
    print(tb::run_towed_wheel(c), c.cell);
    return 0;
  }
  const tb::TerrainCase kind = which == "footprint" ? tb::TerrainCase::footprint : tb::TerrainCase::wheel;
  const int threads = argc > 2 ? std::atoi(argv[2]) : 1;
  const int steps = argc > 3 ? std::atoi(argv[3]) : 400;
  print(tb::run_terrain_case(kind, threads, steps), 0.01);
  return 0;
}
