#pragma once
// Private: the contour map, the second stage of a step. For every column in contact, the
// 8-connected (chessboard) distance in columns to the nearest column that displaced soil
// can reach; displacement carries soil down these levels.

#include <cstddef>
#include <span>
#include <vector>

#include "region.h"

namespace shore::terrain {

class ContourStage {
 public:
  /// Builds the map from the collision flags (ImprintStage::flags).
  void run(const Region& region, std::span<const unsigned char> flags);
  /// Per column: 0 where soil can land, else the distance to such a column.
  [[nodiscard]] std::span<const int> levels() const { return contour_; }
  /// The rows and columns (region-relative) holding every column whose level is above 0
  /// (empty: none).
  [[nodiscard]] const GridRect& closed() const { return closed_; }
  [[nodiscard]] std::size_t bytes() const;

 private:
  void find_open(const Region& region, std::span<const unsigned char> flags);
  /// The chessboard distances relaxed over `closed` (region-relative: the columns that are
  /// not open lie within it).
  void sweep(const Region& region, const GridRect& closed);

  std::vector<int> contour_;
  GridRect closed_;                      ///< closed()
  std::vector<unsigned char> open_;      ///< out of contact and reachable from the open
  std::vector<std::size_t> fill_stack_;  ///< flood fill work list
};

}  // namespace shore::terrain
