#pragma once
// Private: the state behind shore::terrain::Terrain: the settings, the tiles, the volume
// bookkeeping and what carries over between steps, plus the step's working parts.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
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
  /// The change generation in which the palette was last set (0: never, one entry), so a
  /// soil delta sends it only after a change.
  std::uint64_t palette_at = 0;
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

  /// Throws InvalidSetting naming `where`, the entry and the field if the palette is empty
  /// or longer than Terrain::kMaxMaterials, an entry is invalid, an entry's soil_depth differs
  /// from the present material's, or its rigid flag does (entries after 0 may be rigid on a
  /// deforming terrain: bedrock_depth.h). Does not look at the map.
  void check_palette(std::span<const Material> palette, const std::string& where) const;
  /// Makes a checked palette the terrain's, stamped with the current generation.
  void adopt_palette(std::vector<Material> palette);

  [[nodiscard]] std::size_t bytes() const;  ///< all of it, this object included
};

}  // namespace shore::terrain
