#pragma once
// Private: upper bounds of the soil top over square blocks of columns, for a flight's
// landing test: a particle whose whole path in a step stays above the highest column top
// under it cannot land in that step and needs no sampling against the ground
// (spray_flight.h). The blocks tile a window of columns (where the particles in flight can
// be this step, set by cover); each block's bound is its highest top when first asked (the
// bounds live for one spray step, whose SprayGround owns them), raised whenever a column in
// it is raised (SprayGround::set); a column lowered leaves the bound an upper bound. What a
// first ask reads may be kept from earlier steps where the columns cannot have changed
// (UntiledTops, TiledTops): the same value as reading them again.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include "shore/core/grid_rect.h"
#include "spray_tile_index.h"
#include "tile_store.h"

namespace shore::terrain {

/// A block's (or a block's piece's) place: its first column and its size.
struct BlockKey {
  std::int64_t i0 = 0, j0 = 0;
  int nx = 0, ny = 0;
  explicit BlockKey(const GridRect& r) : i0(r.i0), j0(r.j0), nx(r.nx), ny(r.ny) {}
  friend bool operator==(const BlockKey&, const BlockKey&) = default;
};
struct BlockKeyHash {
  std::size_t operator()(const BlockKey& k) const noexcept {
    const auto size = (static_cast<std::size_t>(static_cast<std::uint32_t>(k.nx)) << 32) ^
                      static_cast<std::size_t>(static_cast<std::uint32_t>(k.ny));
    return TileKeyHash{}(TileKey{k.i0, k.j0}) ^ (size * 0x9e3779b97f4a7c15ull);
  }
};

/// Values kept per block (or per block's piece), from step to step: a map bounded to
/// kMostBlocks entries (past that it starts over: a long flight path).
template <class V>
class KeptBlocks {
 public:
  [[nodiscard]] const V* find(const GridRect& r) const {
    const auto it = kept_.find(BlockKey(r));
    return it == kept_.end() ? nullptr : &it->second;
  }
  void keep(const GridRect& r, const V& v) {
    if (kept_.size() >= kMostBlocks) kept_.clear();
    kept_.insert_or_assign(BlockKey(r), v);
  }
  [[nodiscard]] std::size_t bytes() const { return kept_.size() * (sizeof(BlockKey) + sizeof(V) + 16); }

 private:
  static constexpr std::size_t kMostBlocks = 1u << 18;
  std::unordered_map<BlockKey, V, BlockKeyHash> kept_;
};

/// Bounds of blocks (or of a block's piece over one tile) that no tile covers: their tops
/// are the base ground's, which never changes, so the spray keeps them from step to step (a
/// procedural base costs a noise evaluation per column: the rally scene spent half its time
/// re-reading the same untiled blocks). Derived data, not state: never saved or hashed.
class UntiledTops : public KeptBlocks<double> {};

/// Highest tops of blocks (or of a block's piece) that lie in one made tile, kept from step
/// to step with the store's generation when each was read: a tile's change generation
/// (Tile::changed_at, set by every TileStore::mark_changed) below that generation means no
/// height of the tile changed since, so the top kept is the one the heights would give now,
/// to the bit. A tile changed in the generation it was read in, or after, is read again.
/// A released tile held only its base and never changed (changed_at 0), as the one made
/// again in its place. Derived data, not state: never saved or hashed; a loaded terrain
/// starts with none (its spray is new).
class TiledTops {
 public:
  /// The top kept for r, if the tile that holds r has not changed since (changed_at: the
  /// tile's Tile::changed_at); else null.
  [[nodiscard]] const double* find(const GridRect& r, std::uint64_t changed_at) const {
    const Kept* k = kept_.find(r);
    return k == nullptr || !(changed_at < k->read_at) ? nullptr : &k->top;
  }
  /// r's top, read in generation read_at.
  void keep(const GridRect& r, double top, std::uint64_t read_at) { kept_.keep(r, Kept{top, read_at}); }
  [[nodiscard]] std::size_t bytes() const { return kept_.bytes(); }

 private:
  struct Kept {
    double top = 0.0;
    std::uint64_t read_at = 0;
  };
  KeptBlocks<Kept> kept_;
};

class SoilTops {
 public:
  /// untiled, tiled: where bounds of untiled blocks, and of blocks in one tile, are kept
  /// across steps (null: none kept).
  explicit SoilTops(const TileStore& store, UntiledTops* untiled = nullptr, TiledTops* tiled = nullptr)
      : store_(store), index_(store), untiled_(untiled), tiled_(tiled) {}
  /// The window: columns [i0, i1] x [j0, j1]. Blocks have a side of 8 columns or more, so
  /// that at most 64 x 64 of them cover it (a few kB, allocated here).
  void cover(std::int64_t i0, std::int64_t j0, std::int64_t i1, std::int64_t j1);
  /// An upper bound of the soil top over columns [i0, i1] x [j0, j1] (i0 <= i1, j0 <= j1);
  /// +infinity unless the window holds them. Asked for most flights that come near the soil,
  /// hence inline.
  [[nodiscard]] double bound(std::int64_t i0, std::int64_t j0, std::int64_t i1, std::int64_t j1) const {
    const std::int64_t x0 = (i0 >> shift_) - bx0_, x1 = (i1 >> shift_) - bx0_;
    const std::int64_t y0 = (j0 >> shift_) - by0_, y1 = (j1 >> shift_) - by0_;
    if (x0 < 0 || y0 < 0 || x1 >= nbx_ || y1 >= nby_) return std::numeric_limits<double>::infinity();
    double top = -std::numeric_limits<double>::infinity();
    for (std::int64_t y = y0; y <= y1; ++y)
      for (std::int64_t x = x0; x <= x1; ++x) top = std::max(top, block_bound(x, y));
    return top;
  }
  /// An upper bound of the soil top over the whole window (+infinity without one): all its
  /// blocks, computed on the first call if the window holds no more than `most_columns`.
  /// Asked once per particle, so the answer once known costs no call.
  [[nodiscard]] double ceiling(std::int64_t most_columns) const {
    return std::isnan(ceiling_) ? compute_ceiling(most_columns) : ceiling_;
  }
  /// The column (i, j) now has this height. Inline: once per grain laid.
  void raised(std::int64_t i, std::int64_t j, double height) {
    if (!std::isnan(ceiling_)) ceiling_ = std::max(ceiling_, height);
    const std::int64_t x = (i >> shift_) - bx0_, y = (j >> shift_) - by0_;
    if (x < 0 || y < 0 || x >= nbx_ || y >= nby_) return;
    double& b = block_[static_cast<std::size_t>(y * nbx_ + x)];
    if (!std::isnan(b)) b = std::max(b, height);
  }

 private:
  [[nodiscard]] double compute_ceiling(std::int64_t most_columns) const;
  /// The block's bound, computed on first use.
  [[nodiscard]] double block_bound(std::int64_t bx, std::int64_t by) const {
    const double b = block_[static_cast<std::size_t>(by * nbx_ + bx)];
    return std::isnan(b) ? compute_block(bx, by) : b;
  }
  [[nodiscard]] double compute_block(std::int64_t bx, std::int64_t by) const;
  /// A block wider than a tile (a wide window: spray thrown far), tile by tile: a made
  /// tile's rows straight from it, a piece no tile covers from the base, kept across steps.
  /// Read whole through the store instead, each step the rally scene's far spray re-read
  /// 10^7 columns of base (most of them untiled) in blocks that one made tile kept from
  /// being kept.
  [[nodiscard]] double bound_by_tiles(const GridRect& r) const;
  /// The highest top over r (no tile covers it); kept in untiled_ across steps.
  [[nodiscard]] double untiled_bound(const GridRect& r) const;
  /// The highest top over r, which lies in tile t; kept in tiled_ while t does not change.
  [[nodiscard]] double tile_bound(const Tile& t, const GridRect& r) const;

  /// Blocks in a tile of fewer columns are not kept (tile_bound).
  static constexpr std::size_t kKeptColumns = 256;
  const TileStore& store_;
  TileIndex index_;
  int shift_ = 3;                        ///< a block is 2^shift_ columns on a side
  std::int64_t bx0_ = 0, by0_ = 0;       ///< the window's first block (column >> shift_)
  std::int64_t nbx_ = 0, nby_ = 0;       ///< blocks across and along; 0: no window
  mutable double ceiling_ = 0.0;         ///< NaN: not computed yet
  mutable std::vector<double> block_;    ///< nbx_ * nby_ bounds, row-major; NaN: not computed yet
  mutable std::vector<double> heights_;  ///< one block's heights (scratch)
  UntiledTops* untiled_ = nullptr;
  TiledTops* tiled_ = nullptr;
  /// No tile holds a column of r: its heights are all the base's.
  [[nodiscard]] bool untiled(const GridRect& r) const;
};

}  // namespace shore::terrain
