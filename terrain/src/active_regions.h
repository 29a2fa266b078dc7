#pragma once
// Private: where a step works. Only the active regions are gathered and run through the
// pipeline: each pressing imprint's columns within active_reach of the soil, and the boxes
// carried from the last step (slopes left too steep, prints a body may have left), enlarged
// by active_margin (or an imprint's own margin); regions that touch merge.

#include <cstddef>
#include <span>
#include <vector>

#include "shore/terrain/terrain.h"
#include "tile_store.h"

namespace shore::terrain {

/// A box and its margin in columns: a reach box and the columns added around it, or a
/// planned region (without halo) and the margin its slopes still flowing are carried with
/// (the largest of its reach boxes', the terrain's if it holds none).
struct MarginBox {
  GridRect box;
  int margin = 0;
};

class ActiveRegions {
 public:
  /// Bounding box of the columns an imprint covers within active_reach of the soil top; nx
  /// = 0 if none.
  [[nodiscard]] GridRect reach_box(const TileStore& store, const TerrainSettings& s, const Imprint& im);
  /// The step's regions from the reach boxes (each grown by its margin) and the carried
  /// boxes (grown by the terrain's `margin`), in a fixed order. Throws InvalidSetting if one
  /// would exceed kMaxRegionColumns.
  [[nodiscard]] static std::vector<MarginBox> plan(std::span<const MarginBox> reached,
                                                   std::span<const GridRect> carried, int margin);
  /// What is kept to be carried into the next step for `box`, to be grown by `margin` (the
  /// terrain's) then: the box shrunk by margin - `own` on each side, so that it is grown by
  /// `own` in all (no narrower than one column: then by more). The carried boxes stay plain
  /// rectangles, as the state file holds them; the terrain's own margin leaves them as they are.
  [[nodiscard]] static GridRect carry(const GridRect& box, int own, int margin);
  [[nodiscard]] std::size_t bytes() const;

 private:
  std::vector<double> heights_;  ///< soil tops under one imprint
};

}  // namespace shore::terrain
