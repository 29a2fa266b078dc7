#include "kernel.h"

namespace shore::water::kernel {

std::size_t workspace_floats_per_thread(int nx) {
  const std::size_t n = (static_cast<std::size_t>(nx) + 15u) & ~std::size_t{15};
  return 27 * (n + 16) + 16;  // 9 guarded rows of 3 (see take_row3)
}

bool uses_avx2() {
#if !defined(SHORE_WATER_NO_AVX2) && (defined(__x86_64__) || defined(__i386__))
  static const bool has = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return has;
#else
  return false;
#endif
}

Extremes step_3d(const Grid& g, const Coefficients& k, int threads, float* workspace) {
#ifndef SHORE_WATER_NO_AVX2
  if (uses_avx2()) return avx2::step_3d(g, k, threads, workspace);
#endif
  return generic::step_3d(g, k, threads, workspace);
}

void step_vertical(const Grid& g, const Coefficients& k, int threads, float* workspace) {
#ifndef SHORE_WATER_NO_AVX2
  if (uses_avx2()) return avx2::step_vertical(g, k, threads, workspace);
#endif
  generic::step_vertical(g, k, threads, workspace);
}

Extremes measure_3d(const Grid& g, const Coefficients& k, int threads) {
#ifndef SHORE_WATER_NO_AVX2
  if (uses_avx2()) return avx2::measure_3d(g, k, threads);
#endif
  return generic::measure_3d(g, k, threads);
}

}  // namespace shore::water::kernel
