#include "kernel.h"

namespace shore::water::kernel {

std::size_t workspace_bytes(int tile) {
  // 13 force rows of 2 floats + 1 double, 8 measure rows of floats, 1 activity row of doubles,
  // each of tile + 16 entries rounded up to 64 bytes, and slack.
  const std::size_t n = static_cast<std::size_t>(tile) + 16;
  const auto row = [](std::size_t bytes) { return (bytes + 63) & ~std::size_t{63}; };
  return 13 * (2 * row(4 * n) + row(8 * n)) + 8 * row(4 * n) + row(8 * n) + 256;
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
TileResult step_3d(bool, const Tile& t, const Coefficients& k, void* w) { return generic::step_3d(t, k, w); }
TileResult step_vertical(bool, const Tile& t, const Coefficients& k, void* w) {
  return generic::step_vertical(t, k, w);
}
Extremes measure_3d(bool, const Tile& t, const Coefficients& k, void* w) { return generic::measure_3d(t, k, w); }
#else
TileResult step_3d(bool avx2, const Tile& t, const Coefficients& k, void* w) {
  return avx2 ? avx2::step_3d(t, k, w) : generic::step_3d(t, k, w);
}
TileResult step_vertical(bool avx2, const Tile& t, const Coefficients& k, void* w) {
  return avx2 ? avx2::step_vertical(t, k, w) : generic::step_vertical(t, k, w);
}
Extremes measure_3d(bool avx2, const Tile& t, const Coefficients& k, void* w) {
  return avx2 ? avx2::measure_3d(t, k, w) : generic::measure_3d(t, k, w);
}
#endif

}  // namespace shore::water::kernel
