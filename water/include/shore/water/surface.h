#pragma once
// The fast spring-mass water surface (Markichev & Supikov).
//
// State per node: the displacement from the rest position and the velocity. Vertical
// components are fixed-point doubles (exact multiples of a quantum of about 2^-38 of the
// spacing), in-plane components (3-D mode) floats. The displacement form keeps precision
// independent of where the grid sits in the world.
//
// Storage and stepping are in square tiles (SleepSettings): tiles are created when
// something reaches them, step while awake and cost nothing asleep, so a lake of a
// hundred million nodes with one boat costs what its wake costs.
//
// Exactness: springs exchange vertical momentum in rounded, equal and opposite impulses
// and heights rise by rounded increments whose exact sums are known, and the one rounding
// that does not cancel by itself (damping, and velocity times dt) is put back on one node
// each substep. So in a pool without fixed nodes or open edges the total volume (the sum
// of the heights) never changes, to the last bit, over any number of steps.
//
// Kernel: one pass per tile and substep (spring forces, damping, update), vectorised
// (AVX2 + FMA when the CPU has it, chosen at run time; both variants give the same bits).
// ReferenceSurface (reference_surface.h) is the plain form of the same algorithm that
// this one is tested against.
//
// Threads: results are bit-identical for any thread count, tile size and kernel variant.

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "shore/water/disturbance.h"
#include "shore/water/surface_settings.h"

namespace shore::water {

/// What one step(dt) did.
struct StepStats {
  int substeps = 0;           ///< internal substeps taken
  double substep = 0.0;       ///< s, their length
  double simulated = 0.0;     ///< s, time advanced (== dt unless time_clamped)
  double omega_bound = 0.0;   ///< rad/s, the guard's bound on the highest lattice frequency
  bool time_clamped = false;  ///< the guard needed more than max_substeps: time advanced < dt
  int parallel_substeps = 0;  ///< substeps that ran on the team (the rest on one thread)
};

/// Energies in J. Potential is the elastic energy in excess of the rest lattice's
/// (pre-tension) energy: sum over springs of c/2 [(l - L0)^2 - (l_rest - L0)^2]; in
/// vertical-only mode its linearisation k_t/2 sum (w_a - w_b)^2.
struct Energy {
  double kinetic = 0.0;    ///< m/2 sum |v|^2 with the stored v (half a step ahead of x)
  double potential = 0.0;  ///< as above, at the stored positions
  double total = 0.0;      ///< kinetic + potential
  /// Time-centred energy of semi-implicit Euler: m/2 sum v . v_next + potential, v_next the
  /// velocity the next substep (of the last substep's length) would produce. Exactly
  /// conserved by the scheme for undamped linear motion and non-increasing with damping;
  /// the plain total wobbles by about +-(w dt / 2) of a mode's energy.
  double centred = 0.0;
};

/// The guard's deformation measures (see stability.h): max over springs of
/// max(0, 1 - L0 / l), and of sin(angle to the rest direction).
struct Deformation {
  double max_tension = 0.0;
  double max_sin = 0.0;
};

/// A node index pair.
struct NodeIndex {
  int i = 0;
  int j = 0;
};

/// Tiles and their cost right now.
struct TileStats {
  int tile = 0;                  ///< nodes per tile side
  std::int64_t tiles = 0;        ///< tiles covering the grid
  std::int64_t created = 0;      ///< tiles that exist (awake or asleep)
  std::int64_t awake = 0;        ///< tiles that step
  std::int64_t awake_nodes = 0;  ///< nodes in awake tiles
  std::int64_t ever_awake = 0;   ///< tiles that have been awake at least once
  std::size_t memory_bytes = 0;  ///< the surface's own heap memory (tiles, index, scratch)
};

/// A copy of the whole state as dense arrays (node (i, j) at index j * nx + i), for tests and
/// renderers of small grids. In vertical-only mode ux, uy, vx, vy are empty.
struct DenseState {
  std::vector<float> ux, uy, vx, vy;
  std::vector<double> uz, vz;
  std::vector<NodeConstraint> constraints;
};

class Surface {
 public:
  /// Validates the settings (throws shore::InvalidSetting) and builds a surface at rest
  /// with the boundary preset applied.
  explicit Surface(const SurfaceSettings& settings);
  ~Surface();
  Surface(const Surface&) = delete;
  Surface& operator=(const Surface&) = delete;
  Surface(Surface&&) noexcept;
  Surface& operator=(Surface&&) noexcept;

  // ---- stepping -------------------------------------------------------------------------
  /// Advances by dt seconds (finite, > 0), in as many substeps as the guard needs.
  StepStats step(double dt);
  /// Threads for step() (0: the machine's hardware threads). Results do not depend on it.
  void set_threads(int threads);
  /// "avx512", "avx2" or "generic": the kernel KernelChoice::automatic picks on this CPU.
  [[nodiscard]] static const char* fast_kernel_isa();
  /// Whether this build and CPU can run the kernel (automatic and generic always can).
  [[nodiscard]] static bool kernel_available(KernelChoice kernel);
  /// "avx512", "avx2", "generic" or "unfused": the kernel this surface steps with (SurfaceSettings::kernel).
  [[nodiscard]] const char* kernel_isa() const noexcept;
  /// The guard's current bound on the highest lattice frequency (rad/s) from the present
  /// deformation.
  [[nodiscard]] double omega_bound() const;
  [[nodiscard]] const StepStats& last_stats() const;

  // ---- constraints --------------------------------------------------------------------
  /// Sets a node's constraint. A node becoming fixed keeps its present position and loses
  /// its velocity; one becoming vertical-only loses its horizontal velocity. In
  /// vertical-only mode, free and vertical_only mean the same. Wakes the node's tile.
  void set_constraint(int i, int j, NodeConstraint c);
  [[nodiscard]] NodeConstraint constraint(int i, int j) const;
  /// For a coupling that marks the shoreline from terrain: fixed (true) or free (false).
  void set_fixed(int i, int j, bool fixed) {
    set_constraint(i, j, fixed ? NodeConstraint::fixed : NodeConstraint::free);
  }
  [[nodiscard]] bool is_fixed(int i, int j) const { return constraint(i, j) == NodeConstraint::fixed; }
  /// Applies a boundary preset to the four edges (interior nodes keep theirs).
  void apply_boundary(Boundary b);

  // ---- disturbances ---------------------------------------------------------------------
  /// Adds the disturbances in order. All are validated first (finite, positive sizes,
  /// amplitude within the cap); on error nothing is applied. Fixed nodes are not moved.
  void disturb(std::span<const Disturbance> ds);
  void disturb(const Disturbance& d) { disturb(std::span<const Disturbance>(&d, 1)); }
  /// Wakes every tile that covers a node in the world rectangle [x0, x1] x [y0, y1] (and
  /// their neighbours), e.g. under a body. Finite corners, any order.
  void wake(double x0, double y0, double x1, double y1);

  // ---- node access (for a coupling) -------------------------------------------------------
  /// World z of node (i, j) (m).
  [[nodiscard]] double height(int i, int j) const;
  /// Vertical velocity of node (i, j) (m/s).
  [[nodiscard]] double vertical_velocity(int i, int j) const;
  /// Adds dz (m, finite) to node (i, j)'s height, dv (m/s, finite) to its vertical velocity
  /// (rounded to the state's quantum). Fixed nodes are left alone (returns false). Throws on
  /// a non-finite value, a value beyond the disturbance cap, or a bad index.
  /// Every path that changes the state (edits, disturbances, steps) keeps heights within
  /// +-2^50 height quanta (more than 2048 spacings) and vertical velocities within +-2^49
  /// velocity quanta (more than 1024 spacings times the top frequency), saturating there: far
  /// beyond any physical water, it keeps the exact sums exact for any input.
  bool add_height(int i, int j, double dz);
  bool add_vertical_velocity(int i, int j, double dv);
  /// Heights above rest (m) of the nodes [i0, i0 + w) x [j0, j0 + h), row-major, for a
  /// coupling; nodes beyond the grid read as their nearest edge node.
  void heights_above_rest(int i0, int j0, int w, int h, std::vector<double>& out) const;
  /// Vertical velocities of the same window (m/s).
  void vertical_velocities(int i0, int j0, int w, int h, std::vector<double>& out) const;
  /// Adds dz[k] (m, finite, |dz| within the disturbance cap) to the nodes of the window
  /// (row-major, w * h values; nodes beyond the grid and fixed nodes are skipped) and wakes
  /// them. Returns the volume actually added (m^3, exact: the sum of the rounded changes
  /// times h^2).
  double add_heights(int i0, int j0, int w, int h, std::span<const double> dz);
  /// World position and velocity of a node (3-D).
  [[nodiscard]] Eigen::Vector3d position(int i, int j) const;
  [[nodiscard]] Eigen::Vector3d velocity(int i, int j) const;

  // ---- world <-> node ---------------------------------------------------------------------
  /// Rest position of node (i, j) in the horizontal plane.
  [[nodiscard]] double node_x(int i) const { return settings_.origin_x + i * settings_.lattice.spacing; }
  [[nodiscard]] double node_y(int j) const { return settings_.origin_y + j * settings_.lattice.spacing; }
  /// Continuous grid coordinates (i, j) of a world point: (x - origin_x) / h, ...
  [[nodiscard]] Eigen::Vector2d grid_coordinates(double x, double y) const;
  /// The node nearest to a world point, if the point lies within half a cell of the grid.
  [[nodiscard]] std::optional<NodeIndex> nearest_node(double x, double y) const;
  /// Whether a world point lies over the grid's rest footprint.
  [[nodiscard]] bool contains(double x, double y) const;
  /// World z and vertical velocity at a world point: bilinear over the four nodes of the
  /// cell containing it (by rest positions; in 3-D mode the nodes' horizontal drift is
  /// ignored). Points outside the footprint are clamped to its edge.
  [[nodiscard]] double height_at(double x, double y) const;
  [[nodiscard]] double vertical_velocity_at(double x, double y) const;
  /// The water level around a point: the mean of height_at on a circle of `radius` (m, > 0)
  /// around (x, y), 32 points: the level a floater at (x, y) sits in, free of the surface
  /// under the body itself.
  [[nodiscard]] double level_around(double x, double y, double radius) const;

  // ---- totals ----------------------------------------------------------------------------
  /// The water above the rest level (m^3): h^2 times the exact sum of z - rest_height over
  /// every node (each node stands for a column of h x h). Exact: it changes only through
  /// the physics (fixed nodes, open edges, damping of a net vertical momentum) and edits.
  [[nodiscard]] double volume() const;
  /// rest_height + volume() / (nx ny h^2): the mean height over all nodes (fixed ones
  /// counted at their height), m.
  [[nodiscard]] double mean_level() const;

  // ---- output ----------------------------------------------------------------------------
  /// World positions, xyz per node, node (i, j) at index j * nx + i.
  void positions(std::vector<float>& xyz) const;
  /// Unit normals per node from the 4 neighbours: (P(i+1,j) - P(i-1,j)) x (P(i,j+1) - P(i,j-1))
  /// with one-sided differences at edges; same layout as positions().
  void normals(std::vector<float>& xyz) const;
  /// The triangle index buffer of this grid (see triangulate()).
  void triangles(std::vector<std::uint32_t>& indices) const;
  [[nodiscard]] Energy energy() const;
  /// FNV-1a over the grid size, the mode and, tile by tile, the constraints and the state of
  /// every node (tiles not created count as at rest, sleeping tiles as they are): the same
  /// for the same state whatever sleeps or exists.
  [[nodiscard]] std::uint64_t state_hash() const;
  /// Tile counts, awake nodes and memory.
  [[nodiscard]] TileStats tile_stats() const;
  /// Whether the tile holding node (i, j) steps (exists and is awake).
  [[nodiscard]] bool awake(int i, int j) const;

  [[nodiscard]] const SurfaceSettings& settings() const { return settings_; }
  [[nodiscard]] int nx() const { return settings_.nx; }
  [[nodiscard]] int ny() const { return settings_.ny; }
  [[nodiscard]] std::size_t node_count() const {
    return static_cast<std::size_t>(nx()) * static_cast<std::size_t>(ny());
  }
  [[nodiscard]] double spacing() const { return settings_.lattice.spacing; }
  [[nodiscard]] double density() const { return settings_.density; }
  [[nodiscard]] SurfaceMode mode() const { return settings_.mode; }
  /// Total time advanced by step() so far (s).
  [[nodiscard]] double time() const;
  /// The sleep thresholds in use (m, m/s): SleepSettings with its defaults resolved.
  [[nodiscard]] double sleep_height() const;
  [[nodiscard]] double sleep_velocity() const;

  /// The whole evolving state as bytes (shore/core/checkpoint_file.h embeds them): the
  /// created tiles' nodes, constraints, edge snapshots and sleep counters, the time and the
  /// guard's memory. Not the settings: restore_state takes a surface built with the same
  /// ones, and the continued run is bit-identical to the uninterrupted one. restore_state
  /// throws shore::FileError naming `source` (the surface unchanged) on bytes of another
  /// version or grid, or truncated or corrupt ones.
  [[nodiscard]] std::vector<unsigned char> save_state() const;
  void restore_state(std::span<const unsigned char> bytes, const std::string& source);

  /// A dense copy of the state (small grids: nx * ny * 33 bytes).
  [[nodiscard]] DenseState dense_state() const;

  struct State;  ///< opaque: tiles, team, guard

 private:
  SurfaceSettings settings_;
  std::unique_ptr<State> s_;
};

/// The seed paper's triangulation: each cell (i, j)-(i+1, j+1) split along the edge
/// (i+1, j)-(i, j+1) into (i, j), (i+1, j), (i, j+1) and (i, j+1), (i+1, j), (i+1, j+1),
/// counter-clockwise seen from +Z; node (i, j) is vertex j * nx + i. 2 (nx-1)(ny-1)
/// triangles (4802 for the paper's 50 x 50).
void triangulate(int nx, int ny, std::vector<std::uint32_t>& indices);

}  // namespace shore::water
