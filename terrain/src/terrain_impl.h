#pragma once
// Private: the state behind shore::terrain::Terrain: the settings, the tiles, the volume
// bookkeeping and what carries over between steps, plus the step's working parts.

#include <cstddef>
#include <vector>

#include "active_regions.h"
#include "pipeline.h"
#include "shore/terrain/terrain.h"
#include "spray_stage.h"
#include "tile_store.h"

namespace shore::terrain {

struct Terrain::Impl {
  explicit Impl(TerrainSettings settings);

  TerrainSettings s;  ///< validated
  /// The material palette (Terrain::palette), validated; palette[0] equals s.material.
  std::vector<Material> palette;
  TileStore tiles;
  double compacted = 0.0;  ///< m^3
  double edited = 0.0;     ///< m^3 added by set_height
  /// Boxes the next step erodes with or without a body there: slopes the pass cap left too
  /// steep (erosion is rate-limited, not cut off), and the columns the pressing imprints
  /// reached (a body that leaves them no longer holds their slopes).
  std::vector<GridRect> unsettled;
  ActiveRegions planner;
  Pipeline pipeline;
  Spray spray;                 ///< particles in flight, soil clinging to bodies (spray_stage.h)
  double spray_seconds = 0.0;  ///< wall time spent in spray (a measurement, not state)

  [[nodiscard]] std::size_t bytes() const;  ///< all of it, this object included
};

}  // namespace shore::terrain
