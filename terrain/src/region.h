#pragma once
// Private: one active region of a step plus a one-column halo, gathered from the tiles into
// dense arrays for the stages and scattered back afterwards.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "shore/terrain/terrain.h"
#include "tile_store.h"

namespace shore::terrain {

/// No body above a column (envelopes), no limit (caps).
inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// Largest active region (columns, halo included) one step may gather: 64 M columns is
/// ~4 GB of scratch. A body that big is a setup error, reported before any state changes.
inline constexpr std::int64_t kMaxRegionColumns = std::int64_t{1} << 26;

struct Region {
  std::int64_t si0 = 0, sj0 = 0;  ///< global column of region column (0, 0), the halo's corner
  int w = 0, h = 0;               ///< columns, halo included
  bool parallel = false;          ///< rows are shared among `threads`
  int threads = 1;
  std::vector<double> ht;          ///< collision surface, m: the stages move soil here
  std::vector<double> ht_orig;     ///< heights as gathered (scatter reports what changed)
  std::vector<double> ht_pressed;  ///< heights right after collision (what came after is deposit)
  std::vector<double> sink;        ///< plastic sinkage, m
  std::vector<double> bed;         ///< bedrock, m

  /// Takes the rectangle (halo included) and decides whether its rows run in parallel.
  void prepare(const ColumnRect& with_halo, int thread_count, int parallel_min_columns);
  void gather(TileStore& store, double soil_depth);  ///< creates the tiles it touches
  void scatter(TileStore& store) const;              ///< and marks what changed

  [[nodiscard]] std::size_t size() const noexcept { return static_cast<std::size_t>(w) * static_cast<std::size_t>(h); }
  [[nodiscard]] std::size_t at(int x, int y) const noexcept {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
  }
  /// fn(y) for rows [first, last), shared among the threads when the region is parallel.
  /// Each row's task may write only that row's results, so the outcome never depends on the
  /// thread count.
  template <class Fn>
  void for_rows(int first, int last, Fn&& fn) const {
#pragma omp parallel for schedule(static) num_threads(threads) if (parallel)
    for (int y = first; y < last; ++y) fn(y);
  }
  [[nodiscard]] std::size_t bytes() const;
};

}  // namespace shore::terrain
