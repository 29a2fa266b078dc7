// shore_raycast_cost: the driven SoilVehicle of plugin.raycast_wheel_us_per_substep
// (scenes::run_raycast_cost: 4 wheels, 1 cm sand, 1/240 s, one thread), run once and
// printed, for callgrind. A wheel's instructions per substep are a driven run minus a run
// with no driven part (the same settling), over 4 wheels and the driven run's substeps:
//   shore_raycast_cost [seconds driven, default 2] [plane 0|1] [cell m, default 0.01]
//                      [material preset, default sand] [engine force N a wheel, default 500]
//   valgrind --tool=callgrind shore_raycast_cost 2   (and 0; subtract, divide by 4 x 480)
#include <cstdio>
#include <cstdlib>

#include "shore/scenes/raycast_cases.h"

int main(int argc, char** argv) {
  using namespace shore;
  scenes::RaycastCostCase c;
  if (argc > 1) c.seconds = std::atof(argv[1]);
  if (argc > 2) c.on_plane = std::atoi(argv[2]) != 0;
  if (argc > 3) c.cell = std::atof(argv[3]);
  if (argc > 4) c.material = shore::terrain::Material::preset(argv[4]);
  if (argc > 5) c.engine_force = std::atof(argv[5]);
  const scenes::RaycastCostResult r = scenes::run_raycast_cost(c);
  std::printf("%s: %lld substeps driven, %.4f s wall, %.6f m driven\n", c.on_plane ? "plane" : "soil",
              static_cast<long long>(r.substeps), r.wall_seconds, r.distance);
  return 0;
}
