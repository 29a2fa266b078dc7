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

/// Deformation measures of the 3-D lattice for the guard: max over springs of
/// max(0, 1 - L0 / l) and of sin^2(angle to the rest direction).
struct Deformation {
  float max_tension = 0.f;
  float max_sin2 = 0.f;
};

/// Floats of scratch per thread the kernels need for a row of nx nodes.
std::size_t workspace_floats_per_thread(int nx);

// One substep in place. workspace: threads * workspace_floats_per_thread(nx) floats.
void step_3d(const Grid& g, const Coefficients& k, int threads, float* workspace);
void step_vertical(const Grid& g, const Coefficients& k, int threads, float* workspace);
Deformation measure_3d(const Grid& g, const Coefficients& k, int threads, float* workspace);

/// Whether the AVX2 variant runs on this CPU.
bool uses_avx2();

namespace avx2 {
void step_3d(const Grid& g, const Coefficients& k, int threads, float* workspace);
void step_vertical(const Grid& g, const Coefficients& k, int threads, float* workspace);
Deformation measure_3d(const Grid& g, const Coefficients& k, int threads, float* workspace);
}  // namespace avx2
namespace generic {
void step_3d(const Grid& g, const Coefficients& k, int threads, float* workspace);
void step_vertical(const Grid& g, const Coefficients& k, int threads, float* workspace);
Deformation measure_3d(const Grid& g, const Coefficients& k, int threads, float* workspace);
}  // namespace generic

}  // namespace shore::water::kernel
