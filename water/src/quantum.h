#pragma once
// Internal: fixed-point doubles. Heights and vertical velocities are kept as exact
// multiples of a power-of-two quantum Q (about 2^-38 of the spacing, or of spacing times
// the top lattice frequency), within +-2^51 Q. Sums and differences of such values are then
// exact in double arithmetic whatever their order, so the water's volume and vertical
// momentum change only by what the physics says, to the last bit, and every thread count,
// tile size and kernel variant gives the same bits.
//
// round_to(x) = (x + M) - M with M = 1.5 * 2^52 * Q rounds x to the nearest multiple of Q
// (ties to even) with two IEEE additions; count(x) gives the exact integer x / Q for such a
// multiple, from the bits of x / Q + 1.5 * 2^52. Both vectorise without AVX-512 (no
// double-to-int64 instruction needed) and give the same bits in every kernel variant.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

namespace shore::water::quantum {

/// A 128-bit integer for exact sums of many counts (GCC and Clang; __extension__ keeps
/// -Wpedantic quiet).
__extension__ typedef __int128 Wide;

/// 1.5 * 2^52: adding it to |k| < 2^51 puts the integer k in the low mantissa bits.
inline constexpr double kMagic = 6755399441055744.0;
inline constexpr std::int64_t kMagicBits = 0x4338000000000000LL;
/// Bits below the reference scale: Q = 2^(ilogb(scale) - kBits).
inline constexpr int kBits = 38;

struct Quantum {
  double q = 1.0;      ///< the quantum
  double inv = 1.0;    ///< 1 / q (a power of two: x * inv is exact)
  double magic = 1.0;  ///< 1.5 * 2^52 * q
  double keep = 1.0;   ///< 2^keep_bits * q: the state saturates at +-keep (see for_scale)

  /// The quantum for values of order `scale` (> 0, finite): Q = 2^(ilogb(scale) - kBits).
  /// The state's values of this quantum are kept within +-2^keep_bits Q (keep_bits <= 50):
  /// a runaway value saturates there instead of leaving the range where count() is exact,
  /// whose row sums would then overflow (a corrupt or fuzzed state, never a physical one).
  static Quantum for_scale(double scale, int keep_bits) {
    Quantum r;
    const int e = std::ilogb(scale) - kBits;
    r.q = std::ldexp(1.0, e);
    r.inv = std::ldexp(1.0, -e);
    r.magic = kMagic * r.q;
    r.keep = std::ldexp(1.0, keep_bits + e);
    return r;
  }
};

/// Heights (and a substep's rise) are kept within +-2^50 Q_u (more than 2048 spacings),
/// vertical velocities within +-2^49 Q_v (more than 1024 spacings times the top frequency),
/// both beyond the disturbance caps. The rise is clipped too: v dt with the stable substep
/// can reach about 2.5 v / w in units of Q_u / Q_v, so a velocity at its bound could rise
/// by more than 2^51 Q_u. A height plus a clipped rise stays below 2^51 Q_u, exact.
inline constexpr int kKeepBitsHeight = 50;
inline constexpr int kKeepBitsVelocity = 49;

/// x saturated at +-keep (x finite).
inline double saturate(double x, double keep) { return std::min(std::max(x, -keep), keep); }

/// x rounded to the nearest multiple of the quantum whose magic is `magic`.
inline double round_to(double x, double magic) { return (x + magic) - magic; }

/// The exact number of quanta in x, a multiple of the quantum of `inv` with |x| < 2^51 Q.
inline std::int64_t count(double x, double inv) { return std::bit_cast<std::int64_t>(x * inv + kMagic) - kMagicBits; }

}  // namespace shore::water::quantum
