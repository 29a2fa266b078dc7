#pragma once
// Internal: the fast step kernels, compiled twice (AVX2 + FMA, and generic) from
// kernel_impl.inc and chosen at run time.

#include <cstddef>
#include <cstdint>

namespace shore::water::kernel {

/// Float SoA state of an nx x ny grid, index j * nx + i. flags: 0 free, 1 vertical-only,
/// 2 fixed (the NodeConstraint values).
struct Grid {
  int nx = 0;
  int ny = 0;
  float* ux = nullptr;
  float* uy = nullptr;
  float* uz = nullptr;
  float* vx = nullptr;
  float* vy = nullptr;
  float* vz = nullptr;
  const std::uint8_t* flags = nullptr;
};

/// Coefficients of one substep.
struct Coefficients {
  float h = 1.f;          ///< spacing
  float c = 1.f;          ///< spring stiffness (3-D); k_t (vertical-only)
  float rest = 1.f;       ///< axis rest length
  float rest_diag = 1.f;  ///< diagonal rest length
  float damping = 0.f;    ///< gamma, N s/m
  float impulse = 1.f;    ///< dt / m
  float dt = 1.f;
};

/// The guard's raw measures of the 3-D lattice, as bit patterns of non-negative floats
/// (they order like the floats; max and min are exact in any order): per spring family
/// (axis, diagonal) the largest and smallest squared length and the largest squared
/// component across the rest direction; and the largest squared relative velocity
/// |v_b - v_a|^2 of the ends of an axis spring after the substep (a diagonal's is at most
/// twice the square root of it).
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

/// Floats of scratch per thread the kernels need for a row of nx nodes.
std::size_t workspace_floats_per_thread(int nx);

// One substep in place, with the AVX2 variant if avx2 (only where avx2_available()), else
// the generic one. workspace: threads * workspace_floats_per_thread(nx) floats. step_3d
// returns the measures of the positions it started from and the largest relative velocity
// of a spring's ends it ended with.
Extremes step_3d(bool avx2, const Grid& g, const Coefficients& k, int threads, float* workspace);
void step_vertical(bool avx2, const Grid& g, const Coefficients& k, int threads, float* workspace);
Extremes measure_3d(bool avx2, const Grid& g, const Coefficients& k, int threads);

/// Whether this build has the AVX2 variant and this CPU can run it (AVX2 and FMA).
bool avx2_available();

namespace avx2 {
Extremes step_3d(const Grid& g, const Coefficients& k, int threads, float* workspace);
void step_vertical(const Grid& g, const Coefficients& k, int threads, float* workspace);
Extremes measure_3d(const Grid& g, const Coefficients& k, int threads);
}  // namespace avx2
namespace generic {
Extremes step_3d(const Grid& g, const Coefficients& k, int threads, float* workspace);
void step_vertical(const Grid& g, const Coefficients& k, int threads, float* workspace);
Extremes measure_3d(const Grid& g, const Coefficients& k, int threads);
}  // namespace generic

}  // namespace shore::water::kernel
