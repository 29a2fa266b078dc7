#pragma once
// Private: one active region of a step plus a one-column halo, gathered from the tiles into
// dense arrays for the stages and scattered back afterwards.

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "bedrock_depth.h"
#include "layers.h"
#include "shore/core/team.h"
#include "shore/terrain/terrain.h"
#include "tile_store.h"

namespace shore::terrain {

/// No body above a column (envelopes), no limit (caps).
inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// Largest active region (columns, halo included) one step may gather: 64 M columns is
/// ~4 GB of scratch. A body that big is a setup error, reported before any state changes.
inline constexpr std::int64_t kMaxRegionColumns = std::int64_t{1} << 26;

struct Region {
  std::int64_t si0 = 0, sj0 = 0;   ///< global column of region column (0, 0), the halo's corner
  int w = 0, h = 0;                ///< columns, halo included
  Team* team = nullptr;            ///< rows are shared among its threads; nullptr: one thread
  std::vector<double> ht;          ///< collision surface, m: the stages move soil here
  std::vector<double> ht_pressed;  ///< heights right after collision (ImprintStage::collide sets them;
                                   ///< what came after is deposit)
  std::vector<double> sink;        ///< plastic sinkage, m
  std::vector<double> bed;         ///< bedrock, m
  /// Palette index per column; empty when the palette has one entry (every column is 0,
  /// and the stages take their one material's fast path).
  std::vector<std::uint8_t> mat;
  /// Layering per column (layers.h), as two arrays (each copied from a tile's in one go);
  /// layer[k] reads column k's ColumnLayer.
  struct Layers {
    std::vector<double> boundary;     ///< kNoLayer where not layered
    std::vector<std::uint8_t> lower;  ///< read only where layered
    [[nodiscard]] ColumnLayer operator[](std::size_t k) const noexcept { return {boundary[k], lower[k]}; }
    [[nodiscard]] bool empty() const noexcept { return boundary.empty(); }
    [[nodiscard]] std::size_t size() const noexcept { return boundary.size(); }
  };
  /// Empty while the terrain has no layer (then every stage takes the path it took before
  /// layers).
  Layers layer;
  /// The painted (upper) index per column, kept by expose_layers before it overwrites mat;
  /// empty without layers.
  std::vector<std::uint8_t> upper;
  /// A column whose painted index or layer erosion changed (soil of another material laid
  /// on it, or its top layer given away): what scatter writes to its tile.
  struct Relayered {
    std::size_t k = 0;       ///< region column
    std::uint8_t index = 0;  ///< its painted index
    ColumnLayer layer;       ///< its layering (not layered: kNoLayer)
  };
  std::vector<Relayered> relayered;  ///< set by erosion, cleared by gather

  /// Takes the rectangle (halo included) and the team its rows run on (nullptr: serial).
  void prepare(const GridRect& with_halo, Team* rows_team);
  /// Creates the tiles it touches; fills mat only with_materials, layer only with_layers
  /// (which needs with_materials).
  void gather(TileStore& store, const BedrockDepth& depth, bool with_materials, bool with_layers);
  /// With layers: replaces mat with each column's exposed index (its lower layer's where its
  /// sinkage is beyond its crust), what erosion reads, the painted index going to upper, and
  /// calls on_layered(k, layer) for each layered column k, ascending. mat is not scattered,
  /// so nothing else sees it. Erosion calls it as it starts (ErodeStage::run), so its layer
  /// bookkeeping always reads mat exposed. Without layers: nothing.
  template <class Fn>
  void expose_layers(Fn&& on_layered);
  /// Heights and sinkage back into the tiles, marking what changed (read against the
  /// tiles' heights, which nothing else writes between gather and scatter); and the relayered
  /// columns' painted indices and layers (their tiles marked painted, the store layered).
  void scatter(TileStore& store);

  [[nodiscard]] std::size_t size() const noexcept { return static_cast<std::size_t>(w) * static_cast<std::size_t>(h); }
  [[nodiscard]] std::size_t at(int x, int y) const noexcept {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
  }
  /// fn(y) for rows [first, last), shared among the team's threads in bands of rows when
  /// there is a team. Each row's task may write only that row's results, so the outcome
  /// never depends on the thread count or on which thread ran a band.
  template <class Fn>
  void for_rows(int first, int last, Fn&& fn) const {
    if (!team || last - first < 2) {
      for (int y = first; y < last; ++y) fn(y);
      return;
    }
    // About 8 bands per thread: few claims on the team's counter, and a band left to a
    // descheduled worker is a small share of the work the caller waits for.
    const int rows = last - first;
    const int band = std::max(1, rows / (8 * team->size()));
    team->run((rows + band - 1) / band, [&](int item, int) {
      const int y0 = first + item * band;
      const int y1 = std::min(last, y0 + band);
      for (int y = y0; y < y1; ++y) fn(y);
    });
  }
  [[nodiscard]] std::size_t bytes() const;

 private:
  void scatter_relayered(TileStore& store);
  /// scatter_relayered's scratch: the tiles it wrote (each once, with its first column),
  /// whether it wrote a 0 index or an unlayered column there, and the first such column
  /// of each (local; where the check for an all 0 map or an unlayered tile starts).
  struct Touched {
    Tile* tile = nullptr;
    std::int64_t i0 = 0, j0 = 0;
    bool unpainted = false, unlayered = false;
    std::size_t unpainted_at = 0, unlayered_at = 0;
  };
  std::vector<Touched> touched_;
};

template <class Fn>
void Region::expose_layers(Fn&& on_layered) {
  if (layer.empty()) return;
  upper = mat;
  // Raw pointers: a byte store may alias anything, so indexing the vectors would reload
  // their data pointers per column.
  std::uint8_t* index = mat.data();
  const double* boundary = layer.boundary.data();
  const std::uint8_t* lower = layer.lower.data();
  const double* z = sink.data();
  const std::size_t n = layer.size();
  // 64 columns at a time: first which are layered, as bits (no branch per column), then
  // each layered one. (A branch on "any of these layered" per few columns was mispredicted
  // about every other time along a layered rut, where layered and unlayered columns mix.)
  for (std::size_t k0 = 0; k0 < n; k0 += 64) {
    const std::uint64_t layered = layered_bits(boundary + k0, std::min<std::size_t>(64, n - k0));
    for (std::uint64_t bits = layered; bits != 0; bits &= bits - 1) {
      const std::size_t k = k0 + static_cast<std::size_t>(std::countr_zero(bits));
      const ColumnLayer l{boundary[k], lower[k]};
      index[k] = l.exposed(index[k], z[k]);
      on_layered(k, l);
    }
  }
}

}  // namespace shore::terrain
