#pragma once
// Private: displacement, the third stage of a step. The share alpha of each contact
// column's displaced height is carried outward, split equally among the neighbours with a
// lower contour level, level by level, until it lands on the first ring outside the contact
// area (level 0), which rises. The rest (1 - alpha) is compacted. Alpha is the pressed
// column's material's.

#include <cstddef>
#include <span>
#include <vector>

#include "region.h"

namespace shore::terrain {

class DisplaceStage {
 public:
  /// Moves the displaced soil (ImprintStage::displaced) down the contour levels
  /// (ContourStage::levels) onto region.ht. Returns the compacted height, m (sum over
  /// columns). alpha: per palette entry; a contact column pushes its own material's share
  /// to the rim (region.mat; empty: entry 0 everywhere); a layered column the crust's share
  /// for what it was pressed within its crust and the lower layer's beyond. Serial in a fixed order: cheap, it
  /// visits contact columns only. `closed` (region-relative; ContourStage::closed) holds
  /// every column whose level is above 0: only it is scanned for them.
  double run(Region& region, std::span<const int> levels, const GridRect& closed, std::span<const double> displaced,
             std::span<const double> alpha);
  [[nodiscard]] std::size_t bytes() const;

 private:
  void sort_by_level(std::span<const int> levels, int width, const GridRect& closed, int top_level);

  std::vector<int> count_;          ///< counting sort: columns per level
  std::vector<std::size_t> order_;  ///< contact columns, highest level first
  std::vector<double> carry_;       ///< soil on its way through each contact column
};

}  // namespace shore::terrain
