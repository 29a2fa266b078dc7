#pragma once
// The edges of the settings ranges: substeps of 1/30 s and 1/2000 s, cells of
// 2 mm and 20 cm, bodies from 0.05 kg to 50 t on snow, a 50 m/s impact into mud, and sand
// with each material parameter at an edge of its allowed range. Each is a
// soil reference case (a sphere drop against its energy balance, or a plate against
// Bekker) so its sinkage has an outside reference. Written once: the smoke versions are
// tests (tests/bullet/test_extreme_settings.cpp), the full ones shore-bench's reliability
// sweep.

#include <string>
#include <vector>

#include "shore/scenes/soil_cases.h"

namespace shore::scenes {

struct ExtremeCase {
  std::string name;    ///< [a-z0-9_]+
  std::string what;    ///< one line: the extreme and the case
  bool plate = false;  ///< true: `plate_case`, false: `sphere_case`
  SphereDropCase sphere_case;
  PlateCase plate_case;
};

struct ExtremeResult {
  double sinkage = 0.0;  ///< m, the body's bottom below the original surface at the end
  /// m, the deepest the body's bottom went below it (a plate: its sinkage at the end): what
  /// it pressed, wherever it ended (a ball the impact sets rolling leaves its pit).
  double deepest = 0.0;
  double reference = 0.0;    ///< m, the case's reference, limited to the soil's depth (bedrock bears anything)
  double soil_depth = 0.0;   ///< m, of the material
  bool finite = false;       ///< the sinkage and the soil's volume totals are finite
  std::int64_t rescues = 0;  ///< times the body was lifted back above bedrock
  double wall_seconds = 0.0;
  /// The body's bottom ended above bedrock (less 2 cm): nothing fell through.
  [[nodiscard]] bool above_bedrock() const { return sinkage <= soil_depth + 0.02; }
  [[nodiscard]] double error() const { return sinkage - reference; }  ///< m
};

/// The extremes; smoke: coarser or shorter versions that keep each run to seconds.
std::vector<ExtremeCase> extreme_cases(bool smoke);

ExtremeResult run_extreme(const ExtremeCase& c);

}  // namespace shore::scenes
