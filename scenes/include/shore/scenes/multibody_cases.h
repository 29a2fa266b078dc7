#pragma once
// Reference cases of btMultiBody links on soil (TerrainCoupling::add_link), written once for
// the tests and the benchmark: the validation matrix's plate as a multibody's base, against
// Bekker, and run_wheel's towed wheel on a revolute joint, against the rigid-body wheel of the
// same case (sinkage, resistance and Shore's time).

#include <cstdint>

#include "shore/bullet/ground_frame.h"
#include "shore/scenes/soil_cases.h"

namespace shore::scenes {

/// A free multibody of one base, a square plate, with its weight eased in: the validation
/// matrix's plate (0.2 m, 30 kPa on sandy loam at 22 %), in a Featherstone world whose
/// ground is `frame`.
struct MultiBodyPlateCase {
  SoilRun run = sandy_loam_run();
  double width = 0.2;           ///< m, the plate's side
  double pressure = 30e3;       ///< Pa, its weight over its area
  double ramp_seconds = 3.0;    ///< s, the weight eased in (smoothstep to the power n): it arrives at rest
  double settle_seconds = 0.5;  ///< s after it
  /// sandy loam at 22 % (validation_matrix.h), 1 cm columns, one thread.
  static SoilRun sandy_loam_run();
};
struct MultiBodyPlateResult {
  double sinkage = 0.0;            ///< m, the plate's bottom below the untouched surface
  double bekker = 0.0;             ///< m, Bekker's plate sinkage for the same pressure and width
  double carried = 0.0;            ///< N, the soil's push along up at the end
  double weight = 0.0;             ///< N
  std::int64_t skipped_links = 0;  ///< TerrainCouplingStats::skipped_bodies (must be 0)
};
MultiBodyPlateResult run_multibody_plate(const MultiBodyPlateCase& c);

/// run_wheel's towed case (WheelCase with towed = true) with the wheel a multibody's link: a
/// fixed base, a carriage sliding along x (link 0), a hanger sliding along z (link 1) and the
/// wheel turning about y (link 2), every centre on the axle. The hanger and the wheel weigh
/// the load, the carriage 1 % more; the carriage's speed is restored at every substep.
struct MultiBodyWheelResult {
  double sinkage = 0.0;     ///< m, mean depth over the second half of the tow
  double resistance = 0.0;  ///< N, mean towing force over the second half
  RunStats stats;           ///< the whole run (press and tow): wall and Shore's seconds
  std::int64_t skipped_links = 0;
};
MultiBodyWheelResult run_multibody_wheel(const WheelCase& c);

}  // namespace shore::scenes
