#pragma once
// Water-only reference cases, each against something outside the code, shared by the
// water tests and the benchmark:
//   - the echo of a ring from an edge (open, fixed, vertical-only) against the ring's own
//     amplitude at the distance the echo travels (what a perfect mirror returns);
//   - the volume of a closed pool (a constant of the motion) over many steps;
//   - the time-centred energy of the undamped 3-D lattice at small amplitude (conserved
//     exactly by the scheme for linear motion);
//   - a lake of 1 km x 1 km at 10 cm with a towed boat: creation time, memory against the
//     woken area, cost against the awake nodes.

#include <cstdint>
#include <vector>

#include "shore/water/surface_settings.h"

namespace shore::scenes {

/// A ring (a 1 mm Gaussian bump, sigma 2 cells, 5 cm cells, 0.5 m deep, undamped) 30 nodes
/// from the west edge of the water (the open layer lies beyond it). The echo is the
/// source's height minus that of a run whose edges are too far to echo in the window.
struct EchoCase {
  water::SurfaceMode mode = water::SurfaceMode::vertical_only;
  water::Boundary boundary = water::Boundary::open;
  int width = 32;         ///< open layer, nodes
  double strength = 6.0;  ///< open layer
};
struct EchoResult {
  double reflected = 0.0;  ///< m, the largest echo at the source
  double direct = 0.0;     ///< m, the ring's amplitude at twice the distance
  [[nodiscard]] double ratio() const { return direct > 0.0 ? reflected / direct : 0.0; }
};
EchoResult measure_echo(const EchoCase& c);

/// A closed pool (walls: vertical-only edges, no fixed nodes) of nodes x nodes at 5 cm,
/// 0.5 m deep, damping time 2 s, with a 1 cm bump, stepped at 1/240 s.
struct DriftCase {
  water::SurfaceMode mode = water::SurfaceMode::vertical_only;
  int nodes = 65;
  long steps = 100000;
  bool sleep = true;
  int threads = 1;
};
struct DriftResult {
  double volume_drift = 0.0;  ///< largest |V(t) - V(0)| / bump volume over the run
  bool exact = false;         ///< V(t) == V(0) to the last bit at every check
  double seconds = 0.0;       ///< wall time of the steps
};
DriftResult run_closed_pool(const DriftCase& c);

/// The undamped 3-D lattice (65 x 65 at 5 cm, 0.5 m deep, fixed edges) with a bump of
/// `amplitude` (m, 0.003 h by default) at 1/240 s: the largest rise of the time-centred
/// energy over the run, relative to its start.
struct EnergyCase {
  long steps = 100000;
  double amplitude = 1.5e-4;
};
double energy_gain(const EnergyCase& c);

/// A lake of side x side m at `cell`, depth `depth`, open edges, with a boat (a 2 x 1 m
/// kinematic box at 0.3 m draft, displacing water like a floating one) crossing it at
/// `speed` from the middle.
struct LakeCase {
  double side = 1000.0;   ///< m
  double cell = 0.1;      ///< m
  double depth = 2.0;     ///< m
  double speed = 2.0;     ///< m/s
  double seconds = 20.0;  ///< s
  double substep = 1.0 / 60;
  int threads = 1;
};
struct LakeSample {
  double t = 0.0;                 ///< s
  std::int64_t awake_nodes = 0;   ///< nodes in awake tiles at the sample
  double mean_awake_nodes = 0.0;  ///< nodes awake during the substeps since the last sample, their mean
  std::int64_t woken_nodes = 0;   ///< nodes in tiles ever woken
  std::size_t memory_bytes = 0;   ///< the surface's memory
  double step_ms = 0.0;           ///< ms, mean wall time of water + coupling per substep since the last sample
};
struct LakeResult {
  double creation_ms = 0.0;            ///< ms to construct the surface
  std::size_t empty_memory_bytes = 0;  ///< memory right after construction
  std::int64_t virtual_nodes = 0;      ///< nx * ny
  std::vector<LakeSample> samples;     ///< about one a second
};
LakeResult run_lake(const LakeCase& c);
/// The lake's surface: side / cell + 1 nodes a side, vertical-only, open edges, c.threads.
water::SurfaceSettings lake_surface(const LakeCase& c);

}  // namespace shore::scenes
