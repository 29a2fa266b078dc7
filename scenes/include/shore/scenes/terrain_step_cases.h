#pragma once
// Terrain::step alone, no Bullet: a boot footprint, a rolling wheel and a towed wheel in
// dry sand, each with a prescribed envelope. Shared by shore_terrain_bench,
// shore_terrain_case and shore-bench.

#include <cstdint>
#include <string>

#include "shore/core/envelope.h"

namespace shore::terrain {
class Terrain;
}

namespace shore::scenes {

enum class TerrainCase {
  footprint,    ///< 0.28 m x 0.10 m sole pressed 2 cm over 10 substeps, lifted, 0.35 m stride
  wheel,        ///< D 0.8 m, b 0.2 m wheel rolling at 1 m/s, 3 cm deep; envelope clipped to 0.3 m x 0.2 m
  towed_wheel,  ///< D 0.8 m, b 0.3 m cylinder towed 2 m at 1 m/s, 7 cm deep, whole-body envelope window
};

struct TerrainCaseResult {
  std::string name;
  int threads = 1;
  bool forced_parallel = false;      ///< parallel_min_columns = 0 (split even small regions)
  int steps = 0;                     ///< measured steps
  double ms_per_step = 0.0;          ///< Terrain::step wall time
  double bearing_ms_per_step = 0.0;  ///< bearing wall time: bearing_offset (wheel) or bearing (towed wheel)
  double active_columns = 0.0;       ///< mean per step
  double erosion_passes = 0.0;       ///< mean per step
  double columns_per_second = 0.0;   ///< active columns / step time
  std::uint64_t state_hash = 0;      ///< Terrain::state_hash at the end (compare runs)
  double volume_error = 0.0;         ///< m^3, VolumeTotals::total() at the end (0 up to rounding)
  double bearing_sum = 0.0;          ///< N, sum of every bearing result (compare runs)
};

const char* terrain_case_name(TerrainCase c);

/// The towed wheel (the case the Bullet coupling runs): a horizontal cylinder, axis along
/// y, whose lowest line lies `sinkage` below the flat ground, moved `speed * substep` along
/// x each substep. The envelope window is the body's whole footprint seen from below
/// (2 radius x width), as the coupling rasterizes it, closed form, no Bullet.
struct TowedWheelCase {
  double cell = 0.01;            ///< m, column spacing
  double radius = 0.4;           ///< m
  double width = 0.3;            ///< m
  double sinkage = 0.07;         ///< m below the untouched ground (0)
  double speed = 1.0;            ///< m/s
  double substep = 1.0 / 240.0;  ///< s
  int steps = 480;               ///< substeps in all (2 m at the defaults)
  int measured = 100;            ///< the last `measured` substeps are timed
  int threads = 1;
  bool star = true;  ///< conservative collision surface, as the coupling uses
};

/// Lowest point of a cylinder (axis along y, radius r, axle at (x, y, z)) per column within
/// width / 2 of y, clipped to |column x - x| < half_window.
EnvelopeRaster wheel_envelope(const terrain::Terrain& t, double x, double z, double r, double width, double half_window,
                              double y = 0.0);

/// Runs the towed wheel: Terrain::bearing on the envelope (as the coupling does once per
/// body per substep), then Terrain::step; times the last `measured` substeps.
TerrainCaseResult run_towed_wheel(const TowedWheelCase& c, bool forced_parallel = false);

/// Runs `steps` substeps of a case (after `warmup` unmeasured ones) and reports speed.
/// The towed wheel runs its default TowedWheelCase with `steps` measured at the end.
TerrainCaseResult run_terrain_case(TerrainCase c, int threads, int steps, bool forced_parallel = false,
                                   int warmup = 50);

}  // namespace shore::scenes
