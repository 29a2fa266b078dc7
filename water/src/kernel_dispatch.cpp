#include "kernel.h"

#include "shore/core/cpu_features.h"

namespace shore::water::kernel {

std::size_t workspace_bytes(int tile) {
  // Up to 16 force rows of 2 floats + 1 double, 8 measure rows of floats, 4 more float and 8
  // more double rows (the fused kernel's west column, activity, ends, counts), each of
  // tile + 16 entries rounded up to 64 bytes, the masks of a whole tile (8 + 4 bytes a
  // node), and slack; the unfused kernel needs less.
  const std::size_t n = static_cast<std::size_t>(tile) + 16;
  const auto row = [](std::size_t bytes) { return (bytes + 63) & ~std::size_t{63}; };
  const std::size_t nodes = static_cast<std::size_t>(tile) * static_cast<std::size_t>(tile);
  return 16 * (2 * row(4 * n) + row(8 * n)) + 12 * row(4 * n) + 8 * row(8 * n) + row(8 * nodes) + row(4 * nodes) + 256;
}

bool avx2_available() {
#if !defined(SHORE_WATER_NO_AVX2)
  return cpu_has_avx2_fma();
#else
  return false;
#endif
}

bool avx512_available() {
#if !defined(SHORE_WATER_NO_AVX2)
  return cpu_has_avx512();
#else
  return false;
#endif
}

namespace {
#ifdef SHORE_WATER_NO_AVX2
constexpr bool kAvx2Built = false;  // callers never ask for AVX2 (or AVX-512) when it is not available
#else
constexpr bool kAvx2Built = true;
#endif
/// The function of variant v among the four; avx2 and avx512 only where they were built.
template <class F>
F pick(Variant v, F avx512_fn, F avx2_fn, F generic_fn, F unfused_fn) {
  if (v == Variant::unfused) return unfused_fn;
  if (!kAvx2Built) return generic_fn;
  return v == Variant::avx512 ? avx512_fn : v == Variant::avx2 ? avx2_fn : generic_fn;
}
}  // namespace

#ifdef SHORE_WATER_NO_AVX2
// Never called (kAvx2Built): lets pick() name the functions.
namespace avx2 {
TileResult step_3d(const Tile& t, const Coefficients& k, void* w) { return generic::step_3d(t, k, w); }
TileResult step_vertical(const Tile& t, const Coefficients& k, void* w) { return generic::step_vertical(t, k, w); }
Extremes measure_3d(const Tile& t, const Coefficients& k, void* w) { return generic::measure_3d(t, k, w); }
double scaled_ghosts(const double* g, const double* o, int n, double* to, std::ptrdiff_t step, double kappa, double m) {
  return generic::scaled_ghosts(g, o, n, to, step, kappa, m);
}
}  // namespace avx2
namespace avx512 {
TileResult step_3d(const Tile& t, const Coefficients& k, void* w) { return generic::step_3d(t, k, w); }
TileResult step_vertical(const Tile& t, const Coefficients& k, void* w) { return generic::step_vertical(t, k, w); }
Extremes measure_3d(const Tile& t, const Coefficients& k, void* w) { return generic::measure_3d(t, k, w); }
double scaled_ghosts(const double* g, const double* o, int n, double* to, std::ptrdiff_t step, double kappa, double m) {
  return generic::scaled_ghosts(g, o, n, to, step, kappa, m);
}
}  // namespace avx512
#endif

TileResult step_3d(Variant v, const Tile& t, const Coefficients& k, void* w) {
  return pick(v, &avx512::step_3d, &avx2::step_3d, &generic::step_3d, &unfused::step_3d)(t, k, w);
}
TileResult step_vertical(Variant v, const Tile& t, const Coefficients& k, void* w) {
  return pick(v, &avx512::step_vertical, &avx2::step_vertical, &generic::step_vertical, &unfused::step_vertical)(t, k,
                                                                                                                 w);
}
Extremes measure_3d(Variant v, const Tile& t, const Coefficients& k, void* w) {
  return pick(v, &avx512::measure_3d, &avx2::measure_3d, &generic::measure_3d, &unfused::measure_3d)(t, k, w);
}
double scaled_ghosts(Variant v, const double* ghosts, const double* own, int count, double* to, std::ptrdiff_t step,
                     double kappa, double magic) {
  return pick(v, &avx512::scaled_ghosts, &avx2::scaled_ghosts, &generic::scaled_ghosts, &generic::scaled_ghosts)(
      ghosts, own, count, to, step, kappa, magic);
}

}  // namespace shore::water::kernel
