// shore_wheel_case: the coupled towed wheel of plugin.wheel_whole_step_ms_per_substep (sand
// preset, D 0.8 m, b 0.3 m, 4 kN, 1 cm, 1/240 s, one thread), run once and printed, for
// before/after comparisons and callgrind. The tow phase's cost is a towed run minus a held run
// (the same ramp and settling), over the tow's substeps:
//   shore_wheel_case towed|held [erosion_passes] [solver_iterations] [spray 0|1] [active_margin] [step_interval]
//   valgrind --tool=callgrind shore_wheel_case towed   (and held; subtract, divide by 480)
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "shore/scenes/soil_cases.h"

int main(int argc, char** argv) {
  using namespace shore;
  scenes::WheelCase c;
  c.run.terrain.material = terrain::Material::sand();
  c.run.terrain.cell = 0.01;
  c.run.substep = 1.0 / 240;
  c.run.terrain.threads = 1;
  c.towed = argc > 1 && std::strcmp(argv[1], "towed") == 0;
  if (argc > 2) c.run.terrain.max_erosion_passes = std::atoi(argv[2]);
  if (argc > 3) c.run.coupling.contact.iterations = std::atoi(argv[3]);
  if (argc > 4) c.run.terrain.spray.enabled = std::atoi(argv[4]) != 0;
  if (argc > 5) c.run.terrain.active_margin = std::atoi(argv[5]);
  if (argc > 6) c.run.coupling.step_interval = std::atof(argv[6]);
  const scenes::WheelResult r = scenes::run_wheel(c);
  std::printf(
      "%s: %lld substeps, whole %.4f s, plugin %.4f s (envelope %.4f, soil %.4f, push %.4f); sinkage %.5f m "
      "(Bekker %.5f), resistance %.1f N (Bekker %.1f), hash %016llx\n",
      c.towed ? "towed" : "held", static_cast<long long>(r.stats.substeps), r.stats.wall_seconds,
      r.stats.plugin_seconds, r.stats.envelope_seconds, r.stats.terrain_seconds, r.stats.push_seconds, r.sinkage,
      r.reference_sinkage, r.resistance, r.reference_resistance, static_cast<unsigned long long>(r.stats.state_hash));
  return 0;
}
