#pragma once
// Private: the collision flags (stage_imprint.h) of eight columns of a row tested at once.
// The eight flag bytes are read as one word (byte j of it column j on a little-endian
// machine, `kFlagLanes`), a test is done in all eight bytes with shifts and masks, and its
// answers (0 or 1 a byte) are stored as bytes or packed into bits. Only integer operations:
// the answers are exactly the column-by-column tests'.

#include <bit>
#include <cstdint>
#include <cstring>

#include "stage_imprint.h"

namespace shore::terrain::flag_lanes {

/// Whether the words' bytes are the columns in order: otherwise callers test column by column.
inline constexpr bool kFlagLanes = std::endian::native == std::endian::little;
inline constexpr std::uint64_t kLowBits = 0x0101010101010101u;  ///< bit 0 of each byte

static_assert(kInterior == 1 && kCovered == 2 && kContact == 4, "the shifts below");

/// Eight flag bytes from p (any alignment).
inline std::uint64_t eight(const unsigned char* p) {
  std::uint64_t v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

/// Per byte: 1 where f & (kCovered | kContact) == kCovered (a pocket's flags), else 0.
inline std::uint64_t covered_only(std::uint64_t lanes) { return (lanes >> 1) & ~(lanes >> 2) & kLowBits; }
/// Per byte: 1 where f & (kInterior | kContact) == kInterior, else 0.
inline std::uint64_t interior_only(std::uint64_t lanes) { return lanes & ~(lanes >> 2) & kLowBits; }
/// Per byte: 1 where f & (kCovered | kContact) is 0 (under no body), else 0.
inline std::uint64_t uncovered(std::uint64_t lanes) { return ~((lanes >> 1) | (lanes >> 2)) & kLowBits; }

/// Eight bytes of 0 or 1 packed into bits 0..7, byte j to bit j: the multiplication adds
/// each byte's bit into the top byte at its own place, and no two into one.
inline std::uint64_t pack(std::uint64_t ones) { return (ones * 0x0102040810204080u) >> 56; }

}  // namespace shore::terrain::flag_lanes
