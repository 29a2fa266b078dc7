#pragma once
// Private: TileStore::key_of and TileStore::local for spray, which asks them for every
// column a particle lands on, a body picks up from, or a bound reads: by shifts and masks
// where the tile side is a power of two (the default, 64), the same integers without the
// two or four integer divisions of floor_div (tens of cycles each); other sides divide as
// the store does.

#include <cstddef>
#include <cstdint>

#include "tile_store.h"

namespace shore::terrain {

class TileIndex {
 public:
  explicit TileIndex(const TileStore& store) : store_(store) {
    const std::int64_t n = store.n();
    if (n > 0 && (n & (n - 1)) == 0)
      while ((std::int64_t{1} << shift_) < n) ++shift_;
    else
      shift_ = -1;
    mask_ = n - 1;
  }
  /// As store.key_of(i, j): an arithmetic shift is a floor division by 2^shift.
  [[nodiscard]] TileKey key_of(std::int64_t i, std::int64_t j) const {
    if (shift_ < 0) return store_.key_of(i, j);
    return {i >> shift_, j >> shift_};
  }
  /// As store.local(i, j): the mask is the non-negative remainder of a floor division.
  [[nodiscard]] std::size_t local(std::int64_t i, std::int64_t j) const {
    if (shift_ < 0) return store_.local(i, j);
    return static_cast<std::size_t>(((j & mask_) << shift_) | (i & mask_));
  }

 private:
  const TileStore& store_;
  int shift_ = 0;  ///< log2 of the tile side; -1: not a power of two
  std::int64_t mask_ = 0;
};

}  // namespace shore::terrain
