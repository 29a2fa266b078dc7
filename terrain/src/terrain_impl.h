#pragma once
// Private: the storage behind shore::terrain::Terrain (tiles, scratch, bookkeeping).

#include <algorithm>
#include <bit>
#include <compare>
#include <cstdint>
#include <memory>
#include <span>
#include <unordered_map>
#include <vector>

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

/// tile_columns^2 columns, row-major (local index = lj * n + li).
struct Tile {
  explicit Tile(int n);
  std::vector<double> height;   ///< collision surface, m
  std::vector<double> sinkage;  ///< plastic sinkage, m
  std::vector<double> base;     ///< untouched ground, sampled once at creation, m
  /// Columns whose height changed since the last take_changed (local, inclusive).
  bool dirty = false;
  int di0 = 0, dj0 = 0, di1 = 0, dj1 = 0;
  void mark_dirty(int li0, int lj0, int li1, int lj1);
};

enum : unsigned char { kInterior = 1, kCovered = 2, kContact = 4 };

/// One bit per column of a w x h scratch, row by row; bits past a row's end stay clear.
// Largest active region (columns, halo included) one step may gather: 64 M columns is
// ~4 GB of scratch. A body that big is a setup error, reported before any state changes.
inline constexpr std::int64_t kMaxRegionColumns = std::int64_t{1} << 26;

struct ColumnBits {
  int w = 0, h = 0, words = 0;  ///< words: 64-bit words per row
  std::vector<std::uint64_t> bits;

  void reset(int width, int height) {
    w = width, h = height, words = (width + 63) / 64;
    bits.assign(static_cast<std::size_t>(words) * static_cast<std::size_t>(height), 0);
  }
  void clear() { std::fill(bits.begin(), bits.end(), 0); }
  [[nodiscard]] std::uint64_t* row(int y) { return bits.data() + static_cast<std::size_t>(y) * words; }
  [[nodiscard]] const std::uint64_t* row(int y) const { return bits.data() + static_cast<std::size_t>(y) * words; }
  void set(int x, int y) { row(y)[x >> 6] |= std::uint64_t{1} << (x & 63); }
  [[nodiscard]] std::uint64_t tail_mask() const {
    return (w & 63) ? (std::uint64_t{1} << (w & 63)) - 1 : ~std::uint64_t{0};
  }
  /// this &= other (same size)
  void keep(const ColumnBits& other) {
    for (std::size_t k = 0; k < bits.size(); ++k) bits[k] &= other.bits[k];
  }
  /// this |= other (same size)
  void add(const ColumnBits& other) {
    for (std::size_t k = 0; k < bits.size(); ++k) bits[k] |= other.bits[k];
  }
  [[nodiscard]] bool any() const {
    return std::any_of(bits.begin(), bits.end(), [](std::uint64_t b) { return b != 0; });
  }
  /// Bounding box of the set columns, in this set's coordinates; nx = 0 if none.
  [[nodiscard]] ColumnRect bounds() const {
    int x0 = w, y0 = h, x1 = -1, y1 = -1;
    for (int y = 0; y < h; ++y)
      for_each_in_row(y, [&](int x) {
        x0 = std::min(x0, x), x1 = std::max(x1, x);
        y0 = std::min(y0, y), y1 = y;
      });
    if (x1 < 0) return {};
    return {x0, y0, x1 - x0 + 1, y1 - y0 + 1};
  }
  /// Calls fn(x) for every set column of row y, left to right.
  template <class Fn>
  void for_each_in_row(int y, Fn&& fn) const {
    const std::uint64_t* r = row(y);
    for (int i = 0; i < words; ++i)
      for (std::uint64_t word = r[i]; word != 0; word &= word - 1) fn(i * 64 + std::countr_zero(word));
  }
};

/// The active region plus a one-column halo, gathered into dense arrays.
struct Scratch {
  std::int64_t si0 = 0, sj0 = 0;  ///< global column of scratch (0, 0)
  int w = 0, h = 0;
  bool parallel = false;
  int threads = 1;
  std::vector<double> ht, ht_orig, sink, bed;
  std::vector<double> ht_pressed;  // heights right after collision (deposits are what came after)
  /// Set by erode when it stopped at max_erosion_passes with slopes still too steep: the
  /// bounding box of the givers of its last pass that had such a pair (global columns), to
  /// carry on with next step; else nx = 0.
  ColumnRect still_flowing;
  std::vector<double> e_plain, e_star, e_coll, e_true, e_hold;
  std::vector<double> disp, carry, q, out, cap;
  std::vector<unsigned char> flags, mask;
  std::vector<unsigned char> cover;  ///< erosion: 1 where the column lies under a body
  ColumnBits givable, overhang, cand, changed, givers, near, recap, steep_givers, live;  ///< erosion column sets
  std::vector<unsigned char> row_flow;
  std::vector<int> contour;
  std::vector<unsigned char> open;      ///< contour map: out of contact and reachable from the open
  std::vector<std::size_t> fill_stack;  ///< contour map: flood fill work list

  void resize(std::int64_t i0, std::int64_t j0, int width, int height);
  [[nodiscard]] std::size_t at(int x, int y) const noexcept {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
  }
  [[nodiscard]] std::size_t bytes() const;
};

struct Terrain::Impl {
  explicit Impl(TerrainSettings settings);

  TerrainSettings s;
  int n = 64;
  double cell_area = 1e-4;
  std::unordered_map<TileKey, std::unique_ptr<Tile>, TileKeyHash> tiles;
  double compacted = 0.0;  ///< m^3
  double edited = 0.0;     ///< m^3 added by set_height
  std::vector<TileKey> dirty_keys;
  Scratch scratch;
  std::vector<double> reach_heights;  ///< soil tops under one imprint (reach_box)
  /// Boxes the next step erodes with or without a body there: slopes the pass cap left too
  /// steep (erosion is rate-limited, not cut off), and the columns the pressing imprints
  /// reached (a body that leaves them no longer holds their slopes).
  std::vector<ColumnRect> unsettled;

  [[nodiscard]] double base_at(std::int64_t i, std::int64_t j) const;
  [[nodiscard]] const Tile* find(TileKey key) const;
  Tile& tile(TileKey key);  ///< creates on first use
  [[nodiscard]] TileKey key_of(std::int64_t i, std::int64_t j) const;
  [[nodiscard]] std::size_t local(std::int64_t i, std::int64_t j) const;
  [[nodiscard]] std::vector<TileKey> sorted_keys() const;
  [[nodiscard]] int thread_count() const;

  template <class Fn>
  void for_each_piece(std::int64_t i0, std::int64_t j0, int w, int h, Fn&& fn);

  void prepare_scratch(Scratch& sc, std::int64_t i0, std::int64_t j0, int w, int h) const;
  void gather(Scratch& sc);
  void scatter(const Scratch& sc);
  void rasterize(Scratch& sc, std::span<const Imprint> imprints) const;
  double collide(Scratch& sc, int& contact_count) const;
  void contour_map(Scratch& sc) const;
  double displace(Scratch& sc) const;
  int erode(Scratch& sc, bool to_rest) const;
  void loosen_deposits(Scratch& sc) const;
  void read_rect(const ColumnRect& r, std::span<double> out, bool base) const;  ///< out sized nx * ny
  [[nodiscard]] ColumnRect reach_box(const Imprint& im);
  [[nodiscard]] std::vector<ColumnRect> active_regions(std::span<const ColumnRect> reached,
                                                       std::span<const ColumnRect> carried) const;
  StepReport run_region(const ColumnRect& region, std::span<const Imprint> imprints);

  struct BearingColumn {
    std::int64_t i, j;
    double top, sink, bed, lower;
  };
  struct BearingInput {
    std::vector<BearingColumn> columns;  ///< covered columns, window order
  };
  [[nodiscard]] BearingInput bearing_input(const EnvelopeRaster& env, bool only_touching, double offset) const;
  [[nodiscard]] Bearing capacity(const BearingInput& in, double offset, bool with_columns) const;
};

}  // namespace shore::terrain
