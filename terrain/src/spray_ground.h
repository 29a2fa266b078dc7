#pragma once
// Private: the soil as spray sees it: column heights anywhere, soil taken off a column's
// top (bodies picking it up) and laid onto it (particles landing, clumps, soil set back
// down). Either change lowers the column's recorded sinkage by the height moved, so the
// soil below keeps its bearing: a body pressing down to the new top feels what it felt at
// the old one (as for deposits, stage "loosen" of the pipeline).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>

#include "bedrock_depth.h"
#include "shore/terrain/terrain.h"
#include "spray_tile_index.h"
#include "spray_tops.h"
#include "tile_store.h"

namespace shore::terrain {

class SprayGround {
 public:
  /// palette: the terrain's (a rigid entry's columns give no soil below their base,
  /// bedrock_depth.h); empty: every column soil_depth deep.
  /// untiled, tiled: the spray's bounds of untiled blocks and of blocks in one tile, kept
  /// across its steps (null: none; SoilTops).
  SprayGround(TileStore& store, const TerrainSettings& s, std::span<const Material> palette = {},
              UntiledTops* untiled = nullptr, TiledTops* tiled = nullptr);

  /// The nearest column, as nearest((x - origin) / cell) rounds it (the same integer).
  [[nodiscard]] std::int64_t column_i(double x) const { return column_of(x - origin_x_); }
  [[nodiscard]] std::int64_t column_j(double y) const { return column_of(y - origin_y_); }
  [[nodiscard]] double x_of(std::int64_t i) const { return origin_x_ + static_cast<double>(i) * cell_; }
  [[nodiscard]] double y_of(std::int64_t j) const { return origin_y_ + static_cast<double>(j) * cell_; }
  [[nodiscard]] double cell() const { return cell_; }
  /// The column's palette index (0 where never painted).
  [[nodiscard]] std::uint8_t material(std::int64_t i, std::int64_t j) const { return store_.material_at(i, j); }
  /// A flight samples the columns it crosses one after another, mostly in one tile: the last
  /// tile found is kept with its corner, so the next column in it costs no hash lookup and
  /// no division (tiles are never released during a spray step; a column with no tile yet
  /// is looked up each time, so a tile created meanwhile is found).
  [[nodiscard]] double height(std::int64_t i, std::int64_t j) const {
    const std::int64_t li = i - last_i0_, lj = j - last_j0_;
    if (last_ != nullptr && li >= 0 && li < n_ && lj >= 0 && lj < n_)
      return last_->height[static_cast<std::size_t>(lj * n_ + li)];
    return height_looked_up(i, j);
  }
  /// An upper bound of the soil top of every column nearest a point of the box
  /// [x0, x1] x [y0, y1], and of the columns next to those (SoilTops::bound).
  /// Inline: asked for most flights that come below the ceiling.
  [[nodiscard]] double top_bound_over(double x0, double y0, double x1, double y1) const {
    std::int64_t c[4];
    if (!columns_around(x0, y0, x1, y1, 2, c)) return std::numeric_limits<double>::infinity();
    return tops_.bound(c[0], c[1], c[2], c[3]);
  }
  /// Where top_bound_over will mostly be asked this step: the box [x0, x1] x [y0, y1]
  /// (elsewhere it answers +infinity).
  void cover(double x0, double y0, double x1, double y1);
  /// An upper bound of the soil top over that whole box (SoilTops::ceiling): cheaper than
  /// top_bound_over for each of `flights` particles, else +infinity.
  [[nodiscard]] double ceiling(std::size_t flights) const {
    return tops_.ceiling(static_cast<std::int64_t>(std::min<std::size_t>(flights, std::size_t{1} << 30)) * 64);
  }
  /// Heights of a rectangle, row-major (one tile lookup per run).
  void heights(const GridRect& r, std::span<double> out) const { store_.read(r, out, false); }
  /// Within the spray's region (SpraySettings bounds)?
  [[nodiscard]] bool inside(double x, double y) const {
    return x >= x_min_ && x <= x_max_ && y >= y_min_ && y <= y_max_;
  }
  /// Takes up to `depth` m off the column's top, never below bedrock; returns the m^3 taken
  /// (what the column's height actually lost, times cell^2).
  double take(std::int64_t i, std::int64_t j, double depth);
  /// Lays `volume` m^3 onto the column; returns the m^3 its height actually gained.
  /// Inline: every grain set down or landed comes here (millions a run in the rally scene).
  double lay(std::int64_t i, std::int64_t j, double volume) {
    if (!(volume > 0.0)) return 0.0;
    ChangedTile& c = changed_tile(index_.key_of(i, j));
    const std::size_t k = index_.local(i, j);
    return set(i, j, c, k, c.tile->height[k] + volume / area_);
  }

 private:
  /// A tile take() or lay() changed during this step, with the box (tile-local columns) of
  /// those marked changed in it so far: the store's pending rectangle and this generation's
  /// log entry of the tile both hold that box (each mark_changed leaves both holding its
  /// column, they only widen, and neither the generation nor a tile's marks are taken
  /// during a spray step), so a column inside it needs no call: mark_changed would return
  /// at once.
  struct ChangedTile {
    TileKey key;
    Tile* tile = nullptr;
    int i0 = 0, j0 = 0, i1 = -1, j1 = -1;  ///< the box marked, inclusive; empty: i1 < i0
  };
  /// Sets the column's height (in its changed tile c, at local index k), lowers its sinkage
  /// by the height moved and marks it changed; returns the m^3 the height moved by (signed).
  double set(std::int64_t i, std::int64_t j, ChangedTile& c, std::size_t k, double height) {
    Tile& t = *c.tile;
    const double before = t.height[k];
    if (height == before) return 0.0;
    t.height[k] = height;
    const double moved = height - before;
    t.sinkage[k] -= std::abs(moved);
    if (moved > 0.0) tops_.raised(i, j, height);
    mark(c, static_cast<int>(i - c.key.tx * n_), static_cast<int>(j - c.key.ty * n_));
    return moved * area_;
  }
  /// store_.mark_changed for one column, unless the tile's box already holds it.
  void mark(ChangedTile& c, int li, int lj) {
    if (li >= c.i0 && li <= c.i1 && lj >= c.j0 && lj <= c.j1) return;
    mark_new(c, li, lj);
  }
  void mark_new(ChangedTile& c, int li, int lj);
  /// The columns whose quotients (x - origin) / cell truncate to those of the box's
  /// corners, widened by `margin`: {i0, j0, i1, j1}. False if the box is too far out.
  /// By a multiplication (within a few ulps of the division column_i makes): truncated, each
  /// quotient lies within a column of its nearest integer, so two columns on each side cover
  /// the box's columns and their neighbours.
  bool columns_around(double x0, double y0, double x1, double y1, std::int64_t margin, std::int64_t (&c)[4]) const {
    const double qx0 = (x0 - origin_x_) * inverse_cell_, qy0 = (y0 - origin_y_) * inverse_cell_;
    const double qx1 = (x1 - origin_x_) * inverse_cell_, qy1 = (y1 - origin_y_) * inverse_cell_;
    constexpr double kFar = 1e15;  // columns: beyond, no bound is worth it
    if (!(std::abs(qx0) < kFar && std::abs(qy0) < kFar && std::abs(qx1) < kFar && std::abs(qy1) < kFar)) return false;
    c[0] = static_cast<std::int64_t>(qx0) - margin, c[1] = static_cast<std::int64_t>(qy0) - margin;
    c[2] = static_cast<std::int64_t>(qx1) + margin, c[3] = static_cast<std::int64_t>(qy1) + margin;
    return true;
  }
  /// store_.tile(key), the tile made if there is none yet; kept in changed_ by the low
  /// bits of its key: landings and soil set down come in runs on a few tiles (each wheel's).
  ChangedTile& changed_tile(const TileKey& key) {
    ChangedTile& c = changed_[seen_slot(key)];
    if (c.tile != nullptr && c.key == key) return c;
    return changed_tile_looked_up(key, c);
  }
  /// Fills slot c with the tile of this key (box empty).
  ChangedTile& changed_tile_looked_up(const TileKey& key, ChangedTile& c);
  /// height() through the tile store, keeping the tile found.
  double height_looked_up(std::int64_t i, std::int64_t j) const;
  /// nearest(d / cell_) by a multiplication where that gives the same integer: d * (1 /
  /// cell_) lies within 3 ulps of d / cell_ (two roundings of 1/2 ulp each, and that of the
  /// reciprocal), and nearest() is monotonic with steps only at half-integers, so a product
  /// farther than kGuard * |q| from any half-integer rounds as the quotient does. Closer (a
  /// column boundary hit within rounding, rare), or far out, the division decides.
  [[nodiscard]] std::int64_t column_of(double d) const {
    const double q = d * inverse_cell_;
    if (std::abs(q) < kFastColumns) {
      const auto k = static_cast<std::int64_t>(q);  // truncated toward zero
      const double rest = q - static_cast<double>(k);
      if (std::abs(std::abs(rest) - 0.5) > kGuard * std::abs(q)) return k + (rest >= 0.5) - (rest <= -0.5);
    }
    return nearest(d / cell_);
  }
  /// Of |q|: far above the 3 ulps (3 * 2^-52 |q|) the product may be off by.
  static constexpr double kGuard = 0x1.0p-44;
  static constexpr double kFastColumns = 0x1.0p40;
  /// std::llround without the library call (the same value for every |x| < 2^62: the
  /// nearest integer, halves away from zero; x - trunc(x) is exact).
  static std::int64_t nearest(double x) {
    if (!(std::abs(x) < 4.6e18)) return std::llround(x);
    std::int64_t k = static_cast<std::int64_t>(x);  // truncated toward zero
    const double rest = x - static_cast<double>(k);
    if (rest >= 0.5) ++k;
    if (rest <= -0.5) --k;
    return k;
  }
  /// A tile found this step, kept in seen_ by the low bits of its key.
  struct SeenTile {
    std::int64_t tx = 0, ty = 0;
    const Tile* tile = nullptr;
  };
  [[nodiscard]] static std::size_t seen_slot(const TileKey& key) {
    return static_cast<std::size_t>((key.tx & 3) | ((key.ty & 3) << 2));
  }
  TileStore& store_;
  TileIndex index_;
  SoilTops tops_;
  /// Flights in different tiles take turns at height(): each would miss last_ and hash its
  /// tile again (tiles are never released during a spray step, so the pointers stay good;
  /// a column with no tile is still looked up each time).
  mutable std::array<SeenTile, 16> seen_{};
  std::int64_t n_;
  mutable const Tile* last_ = nullptr;
  mutable std::int64_t last_i0_ = 0, last_j0_ = 0;  ///< last_'s first column
  /// Tiles take() or lay() changed this step (tiles are never released during a spray step,
  /// and stay where they are when others are made).
  std::array<ChangedTile, 16> changed_{};
  double cell_, inverse_cell_, area_, origin_x_, origin_y_, soil_depth_;
  BedrockDepth depth_;
  double x_min_, x_max_, y_min_, y_max_;
};

}  // namespace shore::terrain
