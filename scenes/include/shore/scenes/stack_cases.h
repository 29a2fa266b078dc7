#pragma once
// Reference case of bodies resting on bodies on soil, written once for the tests and the
// benchmark: a stack of equal boxes set down touching, at rest, on flat soil. The soil under
// the bottom box bears the whole stack's weight, which reaches it through Bullet's contacts
// between the boxes; a rigid-plastic plate released at rest under that weight
// (terrain::bekker::plate_sinkage_released) is the reference for its sinkage.

#include <cstdint>

#include <LinearMath/btVector3.h>

#include "shore/scenes/soil_cases.h"

namespace shore::scenes {

struct StackCase {
  /// The soil (sand by default, on 4 cm columns: the box is 12 columns wide) and the
  /// substep; a Z-up world only.
  SoilRun run = four_centimetre_run();
  int boxes = 3;                               ///< stacked, each on the one below
  double box_mass = 200.0;                     ///< kg, each
  btVector3 half_extents{0.25f, 0.25f, 0.1f};  ///< m, each box's
  double seconds = 6.0;                        ///< s simulated
  /// Sand on 4 cm columns, one thread, at 1/240 s substeps.
  static SoilRun four_centimetre_run();
};

struct StackResult {
  double sinkage = 0.0;      ///< m, the bottom box's base below the untouched surface at the end
  double reference = 0.0;    ///< m, Bekker's plate released under the stack's weight (smaller side)
  double overlap = 0.0;      ///< m, the deepest any box reached into the one below it, over the run
  double late_speed = 0.0;   ///< m/s, the fastest box over the last second
  std::int64_t rescues = 0;  ///< TerrainCouplingStats::rescues
  bool finite = true;        ///< every pose finite at every substep
};

StackResult run_stack(const StackCase& c);

}  // namespace shore::scenes
