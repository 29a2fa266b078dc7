#pragma once
// The spring-mass water surface (Markichev & Supikov): an nx x ny grid of point masses,
// springs on every grid edge and both diagonals, semi-implicit Euler, optional per-node
// constraints, additive disturbances, a stability guard that splits steps into substeps.
//
// Model (3-D mode). Node (i, j) of mass m rests at (origin_x + i h, origin_y + j h, z0).
// Springs join (i, j) to (i+1, j), (i, j+1) with rest length L0 = rest_ratio h, and to
// (i+1, j+1) and between (i+1, j), (i, j+1) with rest length sqrt(2) L0. A spring of
// length l pulls its ends together with force c (l - L0) (Hooke). rest_ratio < 1 puts the
// lattice under tension at rest, which gives small vertical waves the speed
//   c_w = h sqrt(3 c (1 - rest_ratio) / m).
// Damping: a force -gamma v on each node, so an oscillation's amplitude decays as
// exp(-t gamma / (2 m)): e-folding time 2 m / gamma. (The discrete scheme decays by exactly
// sqrt(1 - gamma dt / m) per step for a single mode: rate -ln(1 - gamma dt / m) / (2 dt).)
// Step: v += dt (F(x) - gamma v) / m, then x += dt v (the new v), per node; fixed nodes keep
// v = 0, vertical-only nodes keep a zero horizontal velocity.
//
// Vertical-only mode: see SurfaceMode::vertical_only (linearised; discrete wave equation).
//
// Storage: float structure-of-arrays; in 3-D mode the displacement from the rest position
// (ux, uy, uz) and the velocity (vx, vy, vz) per node; in vertical-only mode uz and vz. The
// displacement form keeps float precision independent of where the grid sits in the world.
//
// Kernel: one fused pass per row and substep (spring forces, damping, update), float
// structure-of-arrays, vectorised (AVX2 + FMA when the CPU has it, chosen at run time),
// OpenMP over blocks of rows. ReferenceSurface (reference_surface.h) is the plain form of
// the same algorithm that this one is tested against.
//
// Threads: results are bit-identical for any thread count (each row is computed by the same
// arithmetic whoever runs it; no reductions across threads in the update).

#include <cstdint>
#include <optional>
#include <span>
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

class Surface {
 public:
  /// Validates the settings (throws shore::InvalidSetting) and builds a surface at rest
  /// with the boundary preset applied.
  explicit Surface(const SurfaceSettings& settings);
  Surface(const Surface&) = delete;  // the state fields point into one owned buffer
  Surface& operator=(const Surface&) = delete;
  Surface(Surface&&) noexcept = default;
  Surface& operator=(Surface&&) noexcept = default;

  // ---- stepping -------------------------------------------------------------------------
  /// Advances by dt seconds (finite, > 0), in as many substeps as the guard needs.
  StepStats step(double dt);
  /// Threads for step() (0: OpenMP's default, at most one per 16384 nodes). Results do not
  /// depend on it.
  void set_threads(int threads);
  /// "avx2" or "generic": the kernel KernelChoice::automatic picks on this CPU.
  [[nodiscard]] static const char* fast_kernel_isa();
  /// Whether this build and CPU can run the kernel (automatic and generic always can).
  [[nodiscard]] static bool kernel_available(KernelChoice kernel);
  /// "avx2" or "generic": the kernel this surface steps with (SurfaceSettings::kernel).
  [[nodiscard]] const char* kernel_isa() const noexcept { return avx2_ ? "avx2" : "generic"; }
  /// The guard's current bound on the highest lattice frequency (rad/s) from the present
  /// deformation.
  [[nodiscard]] double omega_bound() const;
  [[nodiscard]] const StepStats& last_stats() const { return last_stats_; }

  // ---- constraints --------------------------------------------------------------------
  /// Sets a node's constraint. A node becoming fixed keeps its present position and loses
  /// its velocity; one becoming vertical-only loses its horizontal velocity. In
  /// vertical-only mode, free and vertical_only mean the same.
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

  // ---- node access (for a coupling) -------------------------------------------------------
  /// World z of node (i, j) (m).
  [[nodiscard]] double height(int i, int j) const;
  /// Vertical velocity of node (i, j) (m/s).
  [[nodiscard]] double vertical_velocity(int i, int j) const;
  /// Adds dz (m, finite) to node (i, j)'s height, dv (m/s, finite) to its vertical velocity.
  /// Fixed nodes are left alone (returns false). Throws on a non-finite value or a bad index.
  bool add_height(int i, int j, double dz);
  bool add_vertical_velocity(int i, int j, double dv);
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

  // ---- output ----------------------------------------------------------------------------
  /// World positions, xyz per node, node (i, j) at index j * nx + i.
  void positions(std::vector<float>& xyz) const;
  /// Unit normals per node from the 4 neighbours: (P(i+1,j) - P(i-1,j)) x (P(i,j+1) - P(i,j-1))
  /// with one-sided differences at edges; same layout as positions().
  void normals(std::vector<float>& xyz) const;
  /// The triangle index buffer of this grid (see triangulate()).
  void triangles(std::vector<std::uint32_t>& indices) const;
  [[nodiscard]] Energy energy() const;
  /// FNV-1a over the grid size, mode, constraints and the raw float state.
  [[nodiscard]] std::uint64_t state_hash() const;

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
  [[nodiscard]] double time() const { return time_; }

  /// Raw state for tests and renderers: displacement from rest and velocity per node
  /// (index j * nx + i). In vertical-only mode ux, uy, vx, vy are empty.
  struct View {
    std::span<const float> ux, uy, uz, vx, vy, vz;
    std::span<const NodeConstraint> constraints;
  };
  [[nodiscard]] View view() const;

 private:
  [[nodiscard]] std::size_t index(int i, int j) const;
  void check_index(const char* what, int i, int j) const;
  void step_substep(double dt);
  [[nodiscard]] double velocity_cap() const;

  SurfaceSettings settings_;
  int threads_ = 0;
  bool avx2_ = false;  // the step kernel: the AVX2 variant, or the generic one
  /// The float state lives in one buffer, each field staggered by a few cache lines so that
  /// same-index elements of different fields do not share cache sets (power-of-two grids).
  std::vector<float> storage_;
  float* ux_ = nullptr;  // null in vertical-only mode
  float* uy_ = nullptr;
  float* uz_ = nullptr;
  float* vx_ = nullptr;
  float* vy_ = nullptr;
  float* vz_ = nullptr;
  [[nodiscard]] std::span<const float> field(const float* f) const {
    return f ? std::span<const float>(f, node_count()) : std::span<const float>();
  }
  std::vector<NodeConstraint> constraints_;
  mutable std::vector<float> workspace_;  // kernel scratch, per thread
  /// The guard's deformation measures of the current positions (3-D mode): refreshed by
  /// every substep, dropped when positions are edited, re-measured on demand.
  mutable std::optional<Deformation> deformation_;
  StepStats last_stats_;
  double last_substep_ = 0.0;
  double time_ = 0.0;
};

/// The seed paper's triangulation: each cell (i, j)-(i+1, j+1) split along the edge
/// (i+1, j)-(i, j+1) into (i, j), (i+1, j), (i, j+1) and (i, j+1), (i+1, j), (i+1, j+1),
/// counter-clockwise seen from +Z; node (i, j) is vertex j * nx + i. 2 (nx-1)(ny-1)
/// triangles (4802 for the paper's 50 x 50).
void triangulate(int nx, int ny, std::vector<std::uint32_t>& indices);

}  // namespace shore::water
