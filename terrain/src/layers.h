#pragma once
// Private: layers in depth (a crust over soft soil, snow over ice). A layered column keeps,
// besides its palette index (the upper material, the crust), a lower palette index and the
// sinkage at which the crust ends (its boundary d). Its Bekker law has two pieces,
// continuous in pressure:
//
//   p(z) = P_upper(z)                                   z <= d
//   p(z) = P_upper(d) + P_lower(z - d)                  z >  d
//
// with P_m(z) = (k_c,m / b + k_phi,m) z^n_m: within the crust the crust's law; beyond it
// the lower soil adds its own resistance, from fresh, to the pressure the crust reached.
// A column whose sinkage exceeds its boundary is broken through: it reads as its lower
// material everywhere the column's own material decides (alpha, slope limits, shear,
// remoulding, unloading; Terrain::exposed_index).

#include <cstddef>
#include <cstdint>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace shore::terrain {

/// The boundary of a column without a layer: no sinkage reaches it, so the one-piece law
/// is the two-piece law's first piece, bit for bit.
inline constexpr double kNoLayer = std::numeric_limits<double>::infinity();

/// One column's layering.
struct ColumnLayer {
  double boundary = kNoLayer;  ///< sinkage at which the crust ends, m (kNoLayer: none)
  std::uint8_t lower = 0;      ///< the lower material's palette index (read only if layered)

  [[nodiscard]] bool layered() const noexcept { return boundary < kNoLayer; }
  /// The palette index the column shows at sinkage z: the lower's once z is beyond the crust.
  [[nodiscard]] std::uint8_t exposed(std::uint8_t upper, double z) const noexcept {
    return z > boundary ? lower : upper;
  }
};

/// Which of count <= 64 boundaries are layered (< kNoLayer): bit j for boundary[j]. No branch
/// per column, so a caller can visit a row's layered columns by their bits where a test per
/// column (or per few) would be mispredicted along a rut that mixes layered and unlayered.
[[nodiscard]] inline std::uint64_t layered_bits(const double* boundary, std::size_t count) {
  std::uint64_t bits = 0;
  std::size_t j = 0;
#if defined(__SSE2__)
  // Two columns per compare, and a whole word's shifts constants: the scalar loop's compare,
  // set and variable shift per column cost about as much as the mispredictions saved.
  const __m128d none = _mm_set1_pd(kNoLayer);
  const auto two = [&](std::size_t at) __attribute__((always_inline)) {
    return static_cast<std::uint64_t>(_mm_movemask_pd(_mm_cmplt_pd(_mm_loadu_pd(boundary + at), none))) << at;
  };
  if (count == 64) {
#pragma GCC unroll 32
    for (int p = 0; p < 64; p += 2) bits |= two(static_cast<std::size_t>(p));
    return bits;
  }
  for (; j + 2 <= count; j += 2) bits |= two(j);
#endif
  for (; j < count; ++j) bits |= static_cast<std::uint64_t>(boundary[j] < kNoLayer) << j;
  return bits;
}

/// The two-piece law at sinkage z: piece(m, z) is material m's one-piece pressure (0 for
/// z <= 0), Pa.
template <class Piece>
[[nodiscard]] double layered_pressure(const ColumnLayer& layer, std::uint8_t upper, double z, Piece&& piece) {
  if (!(z > layer.boundary)) return piece(upper, z);
  return piece(upper, layer.boundary) + piece(layer.lower, z - layer.boundary);
}

}  // namespace shore::terrain
