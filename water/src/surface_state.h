#pragma once
// Internal: the surface's tiles, their index, the team and the guard's memory. Shared by
// surface.cpp (construction, constraints, node access), surface_step.cpp (the substep,
// conservation, sleeping, threads) and surface_output.cpp (energy, hash, dense copies).

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "kernel.h"
#include "quantum.h"
#include "shore/core/pacer.h"
#include "shore/core/team.h"
#include "shore/water/surface.h"

namespace shore::water {

/// One tile: up to T x T nodes (row stride T) with their edges' snapshots. Only nodes
/// [0, w) x [0, h) exist (tiles at the grid's far edges may be partial).
struct TileData {
  int tx = 0, ty = 0;  ///< tile coordinates
  int w = 0, h = 0;    ///< nodes along x and y
  std::vector<double> uz, vz;
  std::vector<float> ux, uy, vx, vy;  // 3-D only
  std::vector<std::uint8_t> flags;    // NodeConstraint values
  std::vector<double> sponge;         // sigma per node (1/s) where the open boundary's layer reaches; else empty
  /// The kernel's masks of flags (kernel::Tile::moving, free_nodes), remade only when a
  /// constraint changed (masks_stale) rather than every substep; empty where no node is
  /// constrained.
  std::vector<std::uint64_t> moving;
  std::vector<std::uint32_t> free_nodes;
  bool masks_stale = true;
  /// Positions (and in 3-D velocities) of the edge nodes: south row, north row, west column,
  /// east column, T entries each (side s at s * T). Two copies: a substep reads edges[cur]
  /// of its neighbours and writes its own edges[1 - cur].
  struct Edges {
    std::vector<double> z, vz;
    std::vector<float> x, y, vx, vy;
  };
  std::array<Edges, 2> edges;
  int cur = 0;
  bool awake = false;
  bool ever_awake = false;
  int calm = 0;  ///< substeps in a row with activity below the sleep level
  [[nodiscard]] std::size_t at(int i, int j, int stride) const {
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(stride) + static_cast<std::size_t>(i);
  }
};

/// Bytes a tile holds: all of it (bytes_of) and its masks (mask_bytes).
[[nodiscard]] std::size_t bytes_of(const TileData& t);
[[nodiscard]] inline std::size_t mask_bytes(const TileData& t) {
  return t.moving.capacity() * sizeof(std::uint64_t) + t.free_nodes.capacity() * sizeof(std::uint32_t);
}

/// Which side a tile's ghost ring takes from which neighbour: (dx, dy) per SideIndex.
inline constexpr int kSideDx[kernel::kSides] = {0, 0, -1, 1, -1, 1, -1, 1};
inline constexpr int kSideDy[kernel::kSides] = {-1, 1, 0, 0, -1, -1, 1, 1};

/// The activity (in units of the sleep thresholds) above which a tile's edge wakes its
/// neighbour, and below which the tile counts as calm.
inline constexpr double kWakeLevel = 0.25;
inline constexpr double kSleepLevel = 0.5;

/// Per-thread scratch: the gathered block and the kernel's rows.
struct Scratch {
  std::vector<double> bz;
  std::vector<float> bx, by;
  std::vector<unsigned char> rows;  // kernel::workspace_bytes, aligned by hand
  [[nodiscard]] void* workspace() {
    auto p = reinterpret_cast<std::uintptr_t>(rows.data());
    return reinterpret_cast<void*>((p + 63) & ~std::uintptr_t{63});
  }
};

struct Surface::State {
  int T = 32, shift = 5;  ///< tile side and its log2
  int tiles_x = 0, tiles_y = 0;
  std::vector<std::int32_t> slot;  ///< per tile: index into tiles, or -1 (not created: at rest)
  std::vector<std::unique_ptr<TileData>> tiles;
  std::vector<std::int32_t> awake;  ///< slots of awake tiles, ascending
  bool full = false;                ///< SurfaceMode::full_3d
  kernel::Variant variant = kernel::Variant::generic;
  quantum::Quantum qu, qv;  ///< height and velocity quanta
  double sleep_u = 0.0, sleep_v = 0.0;
  std::vector<double> sigma;  ///< open boundary: sigma by node distance from the edge, [0, width)
  double sigma_max = 0.0;

  int threads = 1;
  std::unique_ptr<Team> team;
  std::vector<Scratch> scratch;
  Pacer pacer;  ///< per substep, after the work threshold: whether the team pays (per awake node)

  mutable std::optional<Deformation> deformation;  // 3-D: of the current positions
  StepStats last_stats;
  double last_substep = 0.0;
  double time = 0.0;
  std::int64_t ever_awake = 0;
  /// bytes_of summed over the created tiles, kept as tiles are made and their sponge or
  /// masks change, so memory_bytes (and tile_stats) does not walk every tile.
  std::size_t tile_bytes = 0;

  // ---- tiles ----
  [[nodiscard]] TileData* find(int tx, int ty) const;
  /// The tile (tx, ty), created at rest with its default constraints if needed.
  TileData& obtain(const SurfaceSettings& s, int tx, int ty);
  [[nodiscard]] bool inside(int tx, int ty) const { return tx >= 0 && ty >= 0 && tx < tiles_x && ty < tiles_y; }
  /// Makes the tile and its eight neighbours awake (creating them).
  void wake_around(const SurfaceSettings& s, int tx, int ty);
  void set_awake(TileData& t);
  void rebuild_awake_list();
  /// Rewrites edges[parity] from the tile's storage.
  void refresh_edges(TileData& t, int parity) const;
  /// The open boundary's sigma profile from the settings (empty unless Boundary::open).
  void set_layer(const SurfaceSettings& s);
  /// Recomputes the sponge sigma of a tile (empty where the layer does not reach).
  void fill_sponge(const SurfaceSettings& s, TileData& t) const;
  [[nodiscard]] std::size_t memory_bytes() const;
  /// Remakes the tile's masks from its flags (TileData::moving, free_nodes): moving where a
  /// node is not fixed, free (3-D) where it is free; none where no node is constrained (in
  /// vertical-only mode only fixed nodes count). Not thread-safe (it counts tile_bytes).
  void refresh_masks(TileData& t);

  // ---- blocks ----
  /// Gathers the tile's positions with the ghost ring into the scratch block and fills the
  /// kernel's view of the tile (sides from the neighbours' state, the steps across them).
  /// The fused vertical-only kernels read only the live sides' ghosts (kernel::Tile::bz):
  /// for them the other sides are measured, not copied, and with the substep's
  /// coefficients (`scale`) the live ones are copied as K (kernel::Tile::ring_scaled).
  kernel::Tile gather(TileData& t, Scratch& sc, const kernel::Coefficients* scale = nullptr) const;
  [[nodiscard]] kernel::Side side_of(const TileData& t, int side) const;
};

/// Default constraint of node (i, j) of an nx x ny grid under boundary b.
NodeConstraint default_constraint(Boundary b, int i, int j, int nx, int ny);

}  // namespace shore::water
