#pragma once
// Internal: the tile step kernels, compiled twice (AVX2 + FMA, and generic) from
// kernel_impl.inc and chosen at run time. One call advances one tile by one substep.
//
// A tile holds up to T x T nodes (row stride T). The caller gathers the positions the
// substep starts from into a scratch block with a ghost ring one node wide (the
// neighbours' edges), so the kernel reads old positions from the block and writes the new
// state into the tile's own storage in place: tiles are independent and may run on any
// thread in any order. Every spring is computed from its two ends' old positions by the
// same arithmetic whichever tile computes it, and the force on a node is summed in one
// fixed order, so tile size and thread count never change the bits.

#include <cstddef>
#include <cstdint>

#include "quantum.h"

namespace shore::water::kernel {

/// What the spring to a ghost node is, per side of the tile.
enum class Side : std::uint8_t {
  live = 0,    ///< an awake neighbour: the spring acts in full
  frozen = 1,  ///< a sleeping (or not yet created) neighbour: in-plane force acts, vertical does not
  absent = 2,  ///< beyond the grid: no spring (3-D: the missing pre-tension pull is applied instead)
};
/// Index of the eight sides and corners.
enum SideIndex : int { kSouth = 0, kNorth, kWest, kEast, kSouthWest, kSouthEast, kNorthWest, kNorthEast, kSides };

/// The tile's state and its gathered block. Block pointers point at interior node (0, 0);
/// row r, column i of the block is at [r * block_stride + i] for r, i in [-1, h] x [-1, w].
struct Tile {
  int w = 0, h = 0;      ///< interior nodes
  int stride = 0;        ///< row stride of the tile's storage
  int block_stride = 0;  ///< row stride of the block
  double* uz = nullptr;  ///< storage: height above rest (multiples of the height quantum)
  double* vz = nullptr;  ///< storage: vertical velocity (multiples of the velocity quantum)
  float* ux = nullptr;   ///< storage, 3-D only
  float* uy = nullptr;
  float* vx = nullptr;
  float* vy = nullptr;
  const std::uint8_t* flags = nullptr;  ///< storage: 0 free, 1 vertical-only, 2 fixed
  /// The masks of flags kept with the tile (the surface rebuilds them when a constraint
  /// changes, not every substep): per node of the storage, all ones where the node is not
  /// fixed (moving) and, 3-D, where it is free (free_nodes); both null where no node is
  /// constrained. Where masks_given is false the fused kernels make them from flags.
  bool masks_given = false;
  const std::uint64_t* moving = nullptr;
  const std::uint32_t* free_nodes = nullptr;
  double* bz = nullptr;  ///< block: old heights with the ghost ring (scratch: the
                         ///< vertical-only kernel overwrites it; for the fused
                         ///< vertical-only kernel only the ring's live sides are
                         ///< gathered: it writes the others' K itself)
  /// Vertical-only, fused kernels: the live sides' ghosts in bz are K already
  /// (quantum::round_to(kappa w, v_magic) with this substep's coefficients), not heights.
  bool ring_scaled = false;
  const float* bx = nullptr;  ///< block, 3-D only
  const float* by = nullptr;
  Side sides[kSides] = {};
  /// Activity of the steps between the tile's edges and the ghost ring per side (computed
  /// when gathering: max |u_edge - u_ghost| / sleep height; 0 where the side is absent).
  double boundary_activity[kSides] = {};
  /// The open boundary's sigma per node (1/s, row-major with the storage's stride), or null
  /// where the tile has no sponge: damping 2 sigma v and pull sigma^2 u per unit mass.
  const double* sponge = nullptr;
  /// The tile this thread steps next, brought into the caches a row per row of this one
  /// (both modes), so that its first reads (the gather's copy, the kernel's velocities) do not
  /// stall a pass of their own: rows of `stride` entries, null where there is none. Only
  /// a hint: no value depends on it.
  struct Next {
    const double* uz = nullptr;
    const double* vz = nullptr;
    const float *ux = nullptr, *uy = nullptr, *vx = nullptr, *vy = nullptr;
    int w = 0, h = 0, stride = 0;
  } next;
};

/// Coefficients of one substep.
struct Coefficients {
  float h = 1.f;          ///< spacing
  float c = 1.f;          ///< spring stiffness (3-D); unused in vertical-only mode
  float rest = 1.f;       ///< axis rest length (3-D)
  float rest_diag = 1.f;  ///< diagonal rest length (3-D)
  float s0 = 0.f;         ///< c (1 - rest_ratio): the Hooke factor at rest (3-D)
  float damping = 0.f;    ///< gamma, N s/m (in-plane, float)
  float impulse = 1.f;    ///< dt / m (float)
  float dt = 1.f;
  double impulse_z = 1.0;             ///< dt / m: vertical force to velocity change
  double kappa = 1.0;                 ///< vertical-only: k_t dt / m (velocity change per unit height difference)
  double beta = 0.0;                  ///< gamma dt / m
  double dt_z = 1.0;                  ///< dt
  double u_magic = 1.0, u_inv = 1.0;  ///< height quantum (quantum.h)
  double v_magic = 1.0, v_inv = 1.0;  ///< velocity quantum
  double u_keep = 1.0, v_keep = 1.0;  ///< heights (and rises), velocities saturate at +- these (quantum.h)
  bool activity = true;               ///< measure the stretch part of the activity (false: nothing sleeps)
  double u_scale = 1.0;               ///< 1 / sleep height threshold (activity)
  double v_scale = 1.0;               ///< 1 / sleep velocity threshold
};

/// The guard's raw measures of the 3-D lattice, as bit patterns of non-negative floats
/// (they order like the floats; max and min are exact in any order): per spring family
/// (axis, diagonal) the largest and smallest squared length and the largest squared
/// component across the rest direction; and the largest squared relative velocity
/// |v_b - v_a|^2 of the ends of an axis spring after the substep.
struct Extremes {
  std::uint32_t long_axis = 0u, short_axis = 0x7f7fffffu, across_axis = 0u;
  std::uint32_t long_diag = 0u, short_diag = 0x7f7fffffu, across_diag = 0u;
  std::uint32_t relative = 0u;

  void merge(const Extremes& o) {
    long_axis = long_axis > o.long_axis ? long_axis : o.long_axis;
    short_axis = short_axis < o.short_axis ? short_axis : o.short_axis;
    across_axis = across_axis > o.across_axis ? across_axis : o.across_axis;
    long_diag = long_diag > o.long_diag ? long_diag : o.long_diag;
    short_diag = short_diag < o.short_diag ? short_diag : o.short_diag;
    across_diag = across_diag > o.across_diag ? across_diag : o.across_diag;
    relative = relative > o.relative ? relative : o.relative;
  }
};

/// What one tile's substep reports. Sums are exact counts of quanta over moving nodes.
struct TileResult {
  quantum::Wide v_before = 0;  ///< sum of vertical velocities before the substep
  quantum::Wide damped = 0;    ///< sum of the (rounded) damping impulses gamma dt / m v
  quantum::Wide v_after = 0;   ///< sum of vertical velocities after it
  quantum::Wide rise = 0;      ///< sum of the (rounded) height increments v dt
  /// Activity: max over moving nodes of the stretch |u_a - u_b| of their springs to the
  /// other nodes of the tile (all components) / sleep height and |v| / sleep velocity (and
  /// the steps to the ghost ring, boundary_activity), over the
  /// whole tile, along each side (row or column) and at each corner node (SideIndex order).
  double activity = 0.0;
  double side_activity[kSides] = {};
  Extremes extremes;  ///< 3-D: the springs the tile computed, and relative speeds within it
};

/// Which compiled variant runs: the fused kernels for AVX-512 (512-bit vectors), AVX2 + FMA
/// or the baseline, or the unfused reference (kernel_unfused.inc; the same bits, slower,
/// for the tests).
enum class Variant : std::uint8_t { generic, avx2, unfused, avx512 };

/// Bytes of scratch one thread needs for tiles of up to `tile` nodes per side.
std::size_t workspace_bytes(int tile);

// One substep of one tile with variant v (avx2 only where avx2_available(), avx512 only
// where avx512_available()).
// workspace: workspace_bytes(tile) bytes, 64-byte aligned.
TileResult step_3d(Variant v, const Tile& t, const Coefficients& k, void* workspace);
TileResult step_vertical(Variant v, const Tile& t, const Coefficients& k, void* workspace);
/// The guard's measures of a tile's springs at the block's positions (no update).
Extremes measure_3d(Variant v, const Tile& t, const Coefficients& k, void* workspace);

/// One side of a tile's ghost ring, as gather takes it where the ghosts are copied as K
/// (Tile::ring_scaled): to[q * step] = round(kappa ghosts[q]) to the quantum of `magic`
/// (quantum::round_to, as the kernel's own scaling: the same bits) for q < count, and the
/// largest |ghosts[q] - own[q]| (own: the tile's nodes facing them), the step across the
/// side. Heights are finite. Here (variant v; unfused takes the generic one) so that the
/// loop runs as wide as the kernel's.
double scaled_ghosts(Variant v, const double* ghosts, const double* own, int count, double* to, std::ptrdiff_t step,
                     double kappa, double magic);

/// Whether this build has the AVX2 variant and this CPU can run it (AVX2 and FMA).
bool avx2_available();
/// Whether this build has the AVX-512 variant and this CPU (and OS) can run it (AVX-512 F,
/// VL, DQ and BW besides AVX2 and FMA).
bool avx512_available();

namespace avx2 {
TileResult step_3d(const Tile& t, const Coefficients& k, void* workspace);
TileResult step_vertical(const Tile& t, const Coefficients& k, void* workspace);
Extremes measure_3d(const Tile& t, const Coefficients& k, void* workspace);
double scaled_ghosts(const double* ghosts, const double* own, int count, double* to, std::ptrdiff_t step, double kappa,
                     double magic);
}  // namespace avx2
namespace avx512 {
TileResult step_3d(const Tile& t, const Coefficients& k, void* workspace);
TileResult step_vertical(const Tile& t, const Coefficients& k, void* workspace);
Extremes measure_3d(const Tile& t, const Coefficients& k, void* workspace);
double scaled_ghosts(const double* ghosts, const double* own, int count, double* to, std::ptrdiff_t step, double kappa,
                     double magic);
}  // namespace avx512
namespace generic {
TileResult step_3d(const Tile& t, const Coefficients& k, void* workspace);
TileResult step_vertical(const Tile& t, const Coefficients& k, void* workspace);
Extremes measure_3d(const Tile& t, const Coefficients& k, void* workspace);
double scaled_ghosts(const double* ghosts, const double* own, int count, double* to, std::ptrdiff_t step, double kappa,
                     double magic);
}  // namespace generic
namespace unfused {
TileResult step_3d(const Tile& t, const Coefficients& k, void* workspace);
TileResult step_vertical(const Tile& t, const Coefficients& k, void* workspace);
Extremes measure_3d(const Tile& t, const Coefficients& k, void* workspace);
}  // namespace unfused

}  // namespace shore::water::kernel
