#pragma once
// Private: the soil grid's storage. Columns live in square tiles of n x n, created on first
// write, so a large field costs nothing until touched; a column without a tile is the
// untouched base ground. A tile that holds nothing but the base and that no step has used
// for a while is released again (release_idle), so memory follows the soil that differs
// from the base, not everywhere a body has been.

#include <algorithm>
#include <compare>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <unordered_map>
#include <vector>

#include "layers.h"
#include "shore/core/floor_div.h"
#include "shore/terrain/height_source.h"
#include "shore/terrain/terrain.h"

namespace shore::terrain {

struct TileKey {
  std::int64_t tx = 0, ty = 0;
  friend bool operator==(const TileKey&, const TileKey&) = default;
  friend auto operator<=>(const TileKey&, const TileKey&) = default;
};

struct TileKeyHash {
  std::size_t operator()(const TileKey& k) const noexcept {
    std::uint64_t h = static_cast<std::uint64_t>(k.tx) * 0x9e3779b97f4a7c15ull;
    h ^= static_cast<std::uint64_t>(k.ty) + 0x632be59bd9b4e019ull + (h << 6) + (h >> 2);
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

/// n^2 columns, row-major (local index = lj * n + li).
struct Tile {
  explicit Tile(int n);
  std::vector<double> height;   ///< collision surface, m
  std::vector<double> sinkage;  ///< plastic sinkage, m
  std::vector<double> base;     ///< untouched ground, sampled once at creation, m
  /// Palette index per column; empty while every column is 0 (the one-material terrain's
  /// tiles never hold it). Kept empty whenever it would be all 0 (normalize_material).
  std::vector<std::uint8_t> material;
  /// Layers in depth (layers.h): per column the sinkage at which its crust ends (kNoLayer:
  /// not layered) and its lower palette index. Both empty while no column of the tile is
  /// layered (normalize_layers), as `material` is while nothing is painted.
  std::vector<double> layer_boundary;
  std::vector<std::uint8_t> layer_lower;
  /// The change generation of the last write to `material` or the layers (0: never painted), so a soil
  /// delta can send the tiles repainted since a generation (TileStore::painted_since).
  std::uint64_t painted_at = 0;
  /// Columns whose height changed since the last take_changed (local; empty: none).
  GridRect changed;
  /// The change generation of its last height change (0: never changed), and that
  /// generation's entry in the store's change log.
  std::uint64_t changed_at = 0;
  std::size_t log_entry = 0;
  std::int64_t last_used = 0;  ///< the store's clock when a step last gathered (or created) it
  /// last_used when the tile was last found to differ from the base (not released): it is
  /// not compared again until a step uses it. -1: never compared.
  std::int64_t kept_at = -1;
  /// True if every height equals its base, no column has sinkage and none is painted: the
  /// tile equals no tile.
  [[nodiscard]] bool holds_only_base() const;
  /// Drops the material array if every entry is 0 (the map's default). Looks from column
  /// `near` on first, then wraps round: painted columns cluster (a painted patch), so the
  /// columns near one just turned 0 usually answer at once.
  void normalize_material(std::size_t near = 0);
  /// Drops the layer arrays if no column is layered; `near` as for normalize_material
  /// (layered columns cluster too: a rut, a crust).
  void normalize_layers(std::size_t near = 0);
  [[nodiscard]] bool layered() const noexcept { return !layer_boundary.empty(); }
  /// Column k's layering (not layered where the tile has no layers).
  [[nodiscard]] ColumnLayer layer(std::size_t k) const noexcept {
    return layered() ? ColumnLayer{layer_boundary[k], layer_lower[k]} : ColumnLayer{};
  }
  [[nodiscard]] std::size_t bytes() const;  ///< this tile and its arrays
};

/// One row of a rectangle's columns that lies in one tile.
struct TileRun {
  TileKey key;
  int li = 0, lj = 0;     ///< the run's first column in the tile
  std::size_t local = 0;  ///< its tile-local index, lj * n + li
  int x = 0, y = 0;       ///< the run's first column, relative to the rectangle's corner
  int count = 0;          ///< columns in the run, > 0
};

class TileStore {
 public:
  explicit TileStore(const TerrainSettings& s);

  [[nodiscard]] int n() const noexcept { return n_; }
  /// Untouched ground at a column: the base source, or flat at base_height.
  [[nodiscard]] double base_at(std::int64_t i, std::int64_t j) const;
  /// base_at(i0 + c, j) into out[c], in one call to the base source (HeightSource::row).
  void base_row(std::int64_t i0, std::int64_t j, std::span<double> out) const;
  [[nodiscard]] TileKey key_of(std::int64_t i, std::int64_t j) const { return {floor_div(i, n_), floor_div(j, n_)}; }
  [[nodiscard]] std::size_t local(std::int64_t i, std::int64_t j) const {
    return static_cast<std::size_t>((j - floor_div(j, n_) * n_) * n_ + (i - floor_div(i, n_) * n_));
  }
  [[nodiscard]] const Tile* find(TileKey key) const;
  [[nodiscard]] Tile* find(TileKey key);
  /// Creates the tile (from the base ground) on first use; marks it used now.
  Tile& tile(TileKey key);
  [[nodiscard]] std::size_t size() const noexcept { return tiles_.size(); }
  [[nodiscard]] std::vector<TileKey> sorted_keys() const;

  /// Calls fn(tile, run) for every run of the rectangle, row by row and left to right,
  /// looking each tile up once; tile is null where the columns have no tile yet.
  template <class Fn>
  void for_each_run(const GridRect& r, Fn&& fn) const {
    const auto lookup = [this](TileKey key) { return find(key); };
    walk(r, lookup, fn);
  }
  /// The same, creating the tiles the rectangle touches: fn(Tile&, run).
  template <class Fn>
  void for_each_run_creating(const GridRect& r, Fn&& fn) {
    const auto lookup = [this](TileKey key) { return &tile(key); };
    walk(r, lookup, [&](Tile* t, const TileRun& run) { fn(*t, run); });
  }
  /// The same over the tiles that exist: fn(Tile&, run), columns without a tile skipped.
  template <class Fn>
  void for_each_existing_run(const GridRect& r, Fn&& fn) {
    const auto lookup = [this](TileKey key) {
      const auto it = tiles_.find(key);
      return it == tiles_.end() ? nullptr : it->second.get();
    };
    walk(r, lookup, [&](Tile* t, const TileRun& run) {
      if (t) fn(*t, run);
    });
  }
  /// Palette index of a column (0 without a tile or a painted map).
  [[nodiscard]] std::uint8_t material_at(std::int64_t i, std::int64_t j) const {
    const Tile* t = find(key_of(i, j));
    return t && !t->material.empty() ? t->material[local(i, j)] : std::uint8_t{0};
  }
  /// The column's layering (not layered without a tile or layers).
  [[nodiscard]] ColumnLayer layer_at(std::int64_t i, std::int64_t j) const {
    const Tile* t = find(key_of(i, j));
    return t ? t->layer(local(i, j)) : ColumnLayer{};
  }
  /// Whether any column may be layered: false until a layer is painted or loaded (then the
  /// readers gather the layers; before, they look nothing up).
  [[nodiscard]] bool layered() const noexcept { return layered_; }
  void mark_layered() noexcept { layered_ = true; }
  /// Records that the tile's material array was written in the current generation.
  void mark_painted(Tile& t) const noexcept {
    t.painted_at = generation_;
    last_painted_ = generation_;
  }
  /// The tiles whose material array was written after generation g, in key order
  /// (painted_since(0): every tile ever painted, including those painted back to all 0).
  [[nodiscard]] std::vector<TileKey> painted_since(std::uint64_t g) const;
  /// The largest palette index painted on any tile but those in `skip` (sorted; 0: none),
  /// lower layers' indices included.
  [[nodiscard]] int largest_material(std::span<const TileKey> skip = {}) const;
  /// Heights (base: untouched ground) of a rectangle, row-major into out (nx * ny).
  void read(const GridRect& r, std::span<double> out, bool base) const;

  /// Records that the tile's columns `local` (tile-local indices) changed height.
  void mark_changed(TileKey key, Tile& t, const GridRect& local);
  /// The changed columns since the last call: one rectangle per tile, in key order.
  std::vector<GridRect> take_changed();
  /// Adds a tile built elsewhere (a loaded state), reported whole by take_changed. False
  /// (and the tile dropped) if the key is taken.
  bool adopt(TileKey key, std::unique_ptr<Tile> t);

  // Non-consuming change tracking: every change is stamped with the current generation,
  // which advance_generation() moves on. Any number of observers each remember the
  // generation they last looked at and ask changed_since(it).
  [[nodiscard]] std::uint64_t generation() const noexcept { return generation_; }
  /// Starts a new generation (before a call that may change heights); trims the log.
  void advance_generation();
  /// One rectangle per tile whose heights changed after generation g, in key order: the
  /// bounding box of its changes after g while the log still holds them, else the tile.
  [[nodiscard]] std::vector<GridRect> changed_since(std::uint64_t g) const;

  /// Advances the clock that release_idle measures idleness with (once per step).
  void tick() noexcept { ++clock_; }
  /// Releases the tiles that no step has used for idle_steps ticks, that hold nothing but
  /// the untouched base (Tile::holds_only_base), whose heights never changed (loaded tiles
  /// count as changed) and whose changes have been taken. Looks every kReleaseScanTicks ticks only.
  /// Returns the number released. Results never depend on it: a released tile is recreated
  /// identically when needed.
  std::size_t release_idle(std::int64_t idle_steps);
  static constexpr std::int64_t kReleaseScanTicks = 64;

  [[nodiscard]] std::size_t bytes() const;  ///< heap memory: tiles, hash table, change list

 private:
  [[nodiscard]] bool releasable(Tile& t, std::int64_t idle_steps) const;

  // One band of tiles at a time: its tiles are looked up first (in x order), then its rows
  // are walked run by run.
  template <class Lookup, class Fn>
  void walk(const GridRect& r, Lookup&& lookup, Fn&& fn) const {
    if (r.nx <= 0 || r.ny <= 0) return;
    const std::int64_t n = n_;
    const std::int64_t tx0 = floor_div(r.i0, n), tx1 = floor_div(r.i0 + r.nx - 1, n);
    const std::int64_t ty0 = floor_div(r.j0, n), ty1 = floor_div(r.j0 + r.ny - 1, n);
    std::vector<decltype(lookup(TileKey{}))> band(static_cast<std::size_t>(tx1 - tx0 + 1));
    for (std::int64_t ty = ty0; ty <= ty1; ++ty) {
      for (std::int64_t tx = tx0; tx <= tx1; ++tx) band[static_cast<std::size_t>(tx - tx0)] = lookup(TileKey{tx, ty});
      const std::int64_t cj0 = std::max(r.j0, ty * n), cj1 = std::min(r.j0 + r.ny, (ty + 1) * n);
      for (std::int64_t j = cj0; j < cj1; ++j)
        for (std::int64_t tx = tx0; tx <= tx1; ++tx) {
          const std::int64_t ci0 = std::max(r.i0, tx * n), ci1 = std::min(r.i0 + r.nx, (tx + 1) * n);
          const int li = static_cast<int>(ci0 - tx * n), lj = static_cast<int>(j - ty * n);
          const std::size_t local = static_cast<std::size_t>(lj) * static_cast<std::size_t>(n) + li;
          const int x = static_cast<int>(ci0 - r.i0), y = static_cast<int>(j - r.j0);
          const TileRun run{{tx, ty}, li, lj, local, x, y, static_cast<int>(ci1 - ci0)};
          fn(band[static_cast<std::size_t>(tx - tx0)], run);
        }
    }
  }

  int n_ = 64;
  double cell_ = 0.01, origin_x_ = 0.0, origin_y_ = 0.0, base_height_ = 0.0;
  std::shared_ptr<const HeightSource> base_;
  std::unordered_map<TileKey, std::unique_ptr<Tile>, TileKeyHash> tiles_;
  std::vector<TileKey> dirty_keys_;

  /// One tile's changed columns (local) in one generation.
  struct ChangeEntry {
    std::uint64_t generation = 0;
    TileKey key;
    GridRect local;
  };
  void log_change(TileKey key, Tile& t, const GridRect& local);
  [[nodiscard]] GridRect whole_tile(TileKey key) const;
  std::uint64_t generation_ = 1;  ///< changes are stamped with it; 0 means "before anything"
  /// The generation of the last mark_painted (0: never): painted_since(g >= it) is empty at once.
  mutable std::uint64_t last_painted_ = 0;
  std::vector<ChangeEntry> log_;  ///< in generation order; complete for generations > log_floor_
  std::uint64_t log_floor_ = 0;
  std::int64_t clock_ = 0;
  bool layered_ = false;
};

}  // namespace shore::terrain
