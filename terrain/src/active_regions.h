#pragma once
// Private: where a step works. Only the active regions are gathered and run through the
// pipeline: each pressing imprint's columns within active_reach of the soil, and the boxes
// carried from the last step (slopes left too steep, prints a body may have left), enlarged
// by active_margin; regions that touch merge.

#include <cstddef>
#include <span>
#include <vector>

#include "shore/terrain/terrain.h"
#include "tile_store.h"

namespace shore::terrain {

class ActiveRegions {
 public:
  /// Bounding box of the columns an imprint covers within active_reach of the soil top; nx
  /// = 0 if none.
  [[nodiscard]] GridRect reach_box(const TileStore& store, const TerrainSettings& s, const Imprint& im);
  /// The step's regions (without halo) from the reach boxes and the carried boxes, in a
  /// fixed order. Throws InvalidSetting if one would exceed kMaxRegionColumns.
  [[nodiscard]] static std::vector<GridRect> plan(std::span<const GridRect> reached, std::span<const GridRect> carried,
                                                  int margin);
  [[nodiscard]] std::size_t bytes() const;

 private:
  std::vector<double> heights_;  ///< soil tops under one imprint
};

}  // namespace shore::terrain
