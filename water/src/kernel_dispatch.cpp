#include "kernel.h"

namespace shore::water::kernel {

std::size_t workspace_floats_per_thread(int nx) {
  const std::size_t n = (static_cast<std::size_t>(nx) + 15u) & ~std::size_t{15};
  return 27 * (n + 16) + 16;  // 9 guarded rows of 3 (see take_row3)
}

bool avx2_available() {
#if !defined(SHORE_WATER_NO_AVX2) && (defined(__x86_64__) || defined(__i386__))
  static const bool has = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return has;
#else
  return false;
#endif
}

#ifdef SHORE_WATER_NO_AVX2
// The generic variant only; callers never ask for AVX2 when it is not available.
Extremes step_3d(bool, const Grid& g, const Coefficients& k, int threads, float* workspace) {
  return generic::step_3d(g, k, threads, workspace);
}
void step_vertical(bool, const Grid& g, const Coefficients& k, int threads, float* workspace) {
  generic::step_vertical(g, k, threads, workspace);
}
Extremes measure_3d(bool, const Grid& g, const Coefficients& k, int threads) {
  return generic::measure_3d(g, k, threads);
}
#else
Extremes step_3d(bool avx2, const Grid& g, const Coefficients& k, int threads, float* workspace) {
  return avx2 ? avx2::step_3d(g, k, threads, workspace) : generic::step_3d(g, k, threads, workspace);
}
void step_vertical(bool avx2, const Grid& g, const Coefficients& k, int threads, float* workspace) {
  if (avx2)
    avx2::step_vertical(g, k, threads, workspace);
  else
    generic::step_vertical(g, k, threads, workspace);
}
Extremes measure_3d(bool avx2, const Grid& g, const Coefficients& k, int threads) {
  return avx2 ? avx2::measure_3d(g, k, threads) : generic::measure_3d(g, k, threads);
}
#endif

}  // namespace shore::water::kernel
