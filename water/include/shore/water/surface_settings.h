#pragma once
// Settings of a water surface: grid size and placement, lattice parameters, mode,
// boundary preset (walls, shores or open water), tiles and sleeping, threads and the
// stability guard.
//
// Grid convention (shared with terrain and the plugin): world Z is up; node (i, j) rests at
// (origin_x + i * h, origin_y + j * h, rest_height), i in [0, nx), j in [0, ny), h = spacing.

#include <cstdint>

#include "shore/water/parameters.h"

namespace shore::water {

/// What a node may do. Stored per node; settable at any time (islands, shoreline).
enum class NodeConstraint : std::uint8_t {
  free = 0,           ///< moves in 3-D (in vertical-only mode: moves vertically)
  vertical_only = 1,  ///< horizontal motion suppressed (pool walls)
  fixed = 2,          ///< does not move (shoreline, islands)
};

/// Which constraint the four grid edges get at construction.
enum class Boundary : std::uint8_t {
  fixed,          ///< all edge nodes fixed: waves reflect with inverted sign (shoreline)
  vertical_only,  ///< edge nodes move only vertically: waves reflect without inversion (pool walls)
  free,           ///< no constraint (3-D mode: pre-tension pulls a free edge inwards)
  open,           ///< open water: a sponge layer (OpenBoundarySettings) absorbs arriving waves, so a
                  ///< finite patch behaves as part of a larger lake; edge nodes are vertical-only
};

/// How nodes move.
enum class SurfaceMode : std::uint8_t {
  /// Nodes move in 3-D under the full nonlinear spring forces (the seed paper's model).
  full_3d,
  /// Every node moves only vertically, under the linearised vertical restoring force of the
  /// pre-tensioned springs: m w'' = k_t * sum over the 8 neighbours (w_n - w) - gamma w',
  /// k_t = c (1 - rest_ratio). This is the discrete wave equation with the same
  /// small-amplitude speed c_w as the 3-D mode. State is a height and a vertical velocity per
  /// node (8 bytes instead of 24) and the stable step is about 2.6x longer.
  vertical_only,
};

/// Which compiled step kernel runs. All give the same bits in the default build
/// (SHORE_CROSS_PLATFORM_DETERMINISTIC); forcing one is for tests and benchmarks.
enum class KernelChoice : std::uint8_t {
  automatic,  ///< the widest variant the build has and the CPU runs: avx512 (only in the cross-platform
              ///< deterministic build, SHORE_CROSS_PLATFORM_DETERMINISTIC), else avx2, else generic
  generic,    ///< the baseline-instruction-set variant
  avx2,       ///< the AVX2 + FMA variant: invalid where it is not available
  unfused,    ///< the generic variant as it was before its row passes were fused (a pass per
              ///< spring family and update): the bitwise reference of the tests; slower
  avx512,     ///< the AVX-512 (F, VL, DQ, BW) variant, 512-bit vectors: invalid where it is not available
};

/// Stability guard: each step(dt) is split into enough substeps that the bound on the
/// highest lattice frequency times the substep stays inside the stable range.
struct GuardSettings {
  double safety = 0.9;                       ///< fraction of the stability limit (w dt < 2) used, in (0, 1]
  int max_substeps = 256;                    ///< substeps per step() at most, >= 1. Beyond it the step advances
                                             ///< only max_substeps stable substeps (the water runs slow rather
                                             ///< than explode) and reports StepStats::time_clamped.
  double max_disturbance_spacings = 1000.0;  ///< disturbance cap, > 0: |height| <= this * h,
                                             ///< |velocity| <= this * h * w_rest (w_rest: the
                                             ///< at-rest top lattice frequency)

  void validate() const;
};

/// The absorbing layer of Boundary::open: within `width` nodes of an edge every node feels
/// an extra damping 2 sigma(d) v and a pull sigma(d)^2 u back to rest (per unit mass), with
/// sigma(d) = sigma_max ((width - d) / width)^2 at d nodes from the edge and
/// sigma_max = strength * c_w / (width * h). The pair is the critically damped form
/// (d/dt + sigma)^2 u of a wave entering the layer, and the smooth ramp keeps the layer's
/// own reflection small: a ring's echo is about 3 % of its amplitude at the default (4 % at
/// width 24, 8 % at 16; tests/water/test_surface_open.cpp, and the benchmark's sweep over
/// the width). The layer takes water out: the volume is not kept where an edge is open.
struct OpenBoundarySettings {
  int width = 32;         ///< nodes, the layer's width from each edge, >= 2 (2 * width < nx, ny)
  double strength = 6.0;  ///< dimensionless, sigma_max * width * h / c_w, in (0, 64]
  void validate() const;
};

/// Tiles and sleeping. The surface is stored and stepped in square tiles of `tile` nodes per
/// side. With `enabled`, a tile is created only when something reaches it (creation of a huge
/// surface is instant and costs nothing for still water); an awake tile falls asleep when
/// for `calm_substeps` substeps in a row every node of it has |z - rest| <= height / 2 and
/// |v| <= velocity / 2 (3-D: every component) and no awake neighbour has a node above a
/// quarter of those next to it. A sleeping tile keeps its state (counted by state_hash) and
/// costs nothing: its nodes are frozen and the springs to it carry no vertical force (its
/// water neither leaves nor enters it, so the volume stays exact). Disturbances, edits,
/// constraint changes and wake() wake the tiles they touch and their eight neighbours; a
/// wave arriving at a tile's edge (above a quarter of the thresholds) wakes the neighbour.
/// The difference from a surface where nothing sleeps stays within `height` (tests).
/// Without `enabled`, every tile exists and steps always (the dense grid; the same bits as a
/// sleeping surface where nothing sleeps).
struct SleepSettings {
  bool enabled = true;
  /// Nodes per tile side, a power of two in [8, 256]. 64: fewer instructions than 32 both
  /// dense (each tile row's fixed costs over twice the nodes) and in a sleeping lake with a
  /// moving source, where the coarser sleep wakes more nodes (docs/water.md).
  int tile = 64;
  double height = 0.0;     ///< m, >= 0; 0: 1e-5 * spacing
  double velocity = 0.0;   ///< m/s, >= 0; 0: height * the top vertical lattice frequency
  int calm_substeps = 16;  ///< >= 1
  void validate() const;
};

struct SurfaceSettings {
  int nx = 64;                ///< nodes along x, >= 3
  int ny = 64;                ///< nodes along y, >= 3
  double origin_x = 0.0;      ///< m, world x of node (0, 0), finite
  double origin_y = 0.0;      ///< m, world y of node (0, 0), finite
  double rest_height = 0.0;   ///< m, world z of the surface at rest (z0), finite
  LatticeParameters lattice;  ///< h, m, c, rest_ratio, gamma (default: the seed paper's set)
  double density = 1000.0;    ///< kg/m^3, water density for buoyancy in a coupling, > 0
  SurfaceMode mode = SurfaceMode::full_3d;
  Boundary boundary = Boundary::fixed;
  /// Threads for the step, >= 0 (0: the machine's hardware threads). Results do not depend
  /// on it. The surface keeps its own team (no OpenMP, so no OMP_WAIT_POLICY matters): idle
  /// workers sleep, work is handed out tile by tile, and a worker that wakes late finds
  /// nothing left rather than holding the step up.
  int threads = 0;
  /// A substep forks only when at least this many nodes are awake (below it the wake-up
  /// costs more than it saves), and only while measured parallel substeps are faster than
  /// serial ones (a loaded machine makes them slower: then the step runs on one thread and
  /// re-tries the team at growing intervals). >= 0; 0: always fork when threads > 1, without
  /// measuring (for tests of the parallel path).
  int parallel_min_nodes = 32768;
  GuardSettings guard;
  SleepSettings sleep;
  OpenBoundarySettings open;  ///< used where boundary == Boundary::open
  KernelChoice kernel = KernelChoice::automatic;

  /// Throws shore::InvalidSetting naming the field, the value and the allowed range.
  void validate() const;

  /// The seed paper's surface: 50 x 50 nodes, h 1, m 4, c 7, gamma 0.05 (its dt was 0.4),
  /// with rest_ratio 0.9 for pre-tension.
  static SurfaceSettings paper();
  /// A surface in physical units (cell size, depth or wave speed, damping time, density).
  static SurfaceSettings physical(const PhysicalParameters& p, int nx, int ny);
};

}  // namespace shore::water
