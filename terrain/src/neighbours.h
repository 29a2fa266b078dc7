#pragma once
// Private: the 8 neighbours of a column in a dense row-major grid.

#include <array>
#include <cstddef>

namespace shore::terrain {

/// 8-neighbour directions: 0-3 along the axes (one cell away), 4-7 the diagonals, arranged
/// so the opposite of direction d is d ^ 1.
inline constexpr int kDx[8] = {1, -1, 0, 0, 1, -1, 1, -1};
inline constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, -1, 1};

/// Index offsets of the 8 neighbours in rows of `width` columns, in direction order.
/// Added to a std::size_t index they wrap modulo 2^64, so negative offsets work.
[[nodiscard]] inline std::array<std::size_t, 8> neighbour_offsets(int width) {
  std::array<std::size_t, 8> off{};
  for (int d = 0; d < 8; ++d) off[d] = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(kDy[d]) * width + kDx[d]);
  return off;
}

/// The lowest (highest) of the 4 axis neighbours and of the 4 diagonal neighbours of *p in
/// rows of w: min and max are exact, so the order does not change the values.
struct NeighbourExtremes {
  double axis, diagonal;
};
template <class Pick>
[[nodiscard]] NeighbourExtremes neighbour_extremes(const double* p, std::ptrdiff_t w, Pick pick) {
  return {pick(pick(p[-1], p[1]), pick(p[-w], p[w])), pick(pick(p[-w - 1], p[w + 1]), pick(p[-w + 1], p[w - 1]))};
}

}  // namespace shore::terrain
