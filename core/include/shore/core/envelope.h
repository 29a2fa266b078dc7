#pragma once
// A body's shape seen from above and below, sampled on the soil / water column grid.
//
// Grid convention shared by terrain, water and the plugin: world Z is up; column (i, j)
// stands at x = origin_x + i * cell, y = origin_y + j * cell (columns are grid vertices,
// which is also where btHeightfieldTerrainShape puts its heights).

#include <cstdint>
#include <limits>
#include <vector>

#include "shore/core/grid_rect.h"

namespace shore {

/// Per-column lowest and highest point of one body on the vertical line through each
/// column of a rectangular window. Columns the body does not cover hold lower = +inf and
/// upper = -inf. Heights in metres, world frame. The window is the GridRect.
struct EnvelopeRaster : GridRect {
  std::vector<double> lower;  ///< nx*ny, row-major (GridRect::index)
  std::vector<double> upper;  ///< nx*ny, same layout; may be empty if not needed

  static constexpr double kNoLower = std::numeric_limits<double>::infinity();
  static constexpr double kNoUpper = -std::numeric_limits<double>::infinity();

  void resize(std::int64_t first_i, std::int64_t first_j, int width, int height, bool with_upper) {
    i0 = first_i;
    j0 = first_j;
    nx = width;
    ny = height;
    lower.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), kNoLower);
    upper.assign(with_upper ? lower.size() : 0u, kNoUpper);
  }
  [[nodiscard]] bool covers(std::size_t k) const noexcept { return lower[k] < kNoLower; }
};

}  // namespace shore
