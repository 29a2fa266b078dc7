#pragma once
// The one rectangle of grid points in Shore: soil columns, water nodes, mesh nodes and the
// windows of body envelopes are all addressed by a pair of integer indices (i along x, j
// along y) and grouped in rectangles of this type.

#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace shore {

/// Grid points [i0, i0 + nx) x [j0, j0 + ny). Empty when nx or ny is 0; never negative sizes.
struct GridRect {
  std::int64_t i0 = 0, j0 = 0;
  int nx = 0, ny = 0;

  [[nodiscard]] constexpr std::int64_t i1() const noexcept { return i0 + nx; }  ///< one past the last i
  [[nodiscard]] constexpr std::int64_t j1() const noexcept { return j0 + ny; }  ///< one past the last j
  [[nodiscard]] constexpr bool empty() const noexcept { return nx <= 0 || ny <= 0; }
  [[nodiscard]] constexpr std::size_t size() const noexcept {
    return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
  }
  [[nodiscard]] constexpr bool contains(std::int64_t i, std::int64_t j) const noexcept {
    return i >= i0 && j >= j0 && i < i0 + nx && j < j0 + ny;
  }
  /// Row-major index of (i, j), which the rectangle contains: (j - j0) nx + (i - i0).
  [[nodiscard]] constexpr std::size_t index(std::int64_t i, std::int64_t j) const noexcept {
    return static_cast<std::size_t>((j - j0) * nx + (i - i0));
  }
  /// The rectangle moved by (di, dj).
  [[nodiscard]] constexpr GridRect shifted(std::int64_t di, std::int64_t dj) const noexcept {
    return {i0 + di, j0 + dj, nx, ny};
  }
  /// The rectangle with `n` more points on every side.
  [[nodiscard]] constexpr GridRect grown(int n) const noexcept { return {i0 - n, j0 - n, nx + 2 * n, ny + 2 * n}; }
  /// The rectangle from the first corner to the last, both included.
  [[nodiscard]] static constexpr GridRect spanning(std::int64_t i0, std::int64_t j0, std::int64_t i_last,
                                                   std::int64_t j_last) noexcept {
    return {i0, j0, static_cast<int>(i_last - i0 + 1), static_cast<int>(j_last - j0 + 1)};
  }
  friend constexpr bool operator==(const GridRect&, const GridRect&) = default;
};

/// Whether two rectangles share a point, or only touch along an edge or corner (`touching`).
[[nodiscard]] constexpr bool overlap(const GridRect& a, const GridRect& b, bool touching = false) noexcept {
  const std::int64_t t = touching ? 1 : 0;
  return a.i0 < b.i1() + t && b.i0 < a.i1() + t && a.j0 < b.j1() + t && b.j0 < a.j1() + t;
}

/// The smallest rectangle holding both (an empty one adds nothing). A side beyond int's
/// range saturates at its largest value.
[[nodiscard]] constexpr GridRect bounding(const GridRect& a, const GridRect& b) noexcept {
  if (a.empty()) return b;
  if (b.empty()) return a;
  const std::int64_t i0 = std::min(a.i0, b.i0), j0 = std::min(a.j0, b.j0);
  const std::int64_t nx = std::max(a.i1(), b.i1()) - i0, ny = std::max(a.j1(), b.j1()) - j0;
  constexpr std::int64_t kMax = 0x7fffffff;
  return {i0, j0, static_cast<int>(std::min(nx, kMax)), static_cast<int>(std::min(ny, kMax))};
}

/// The points both rectangles hold (empty if none).
[[nodiscard]] constexpr GridRect intersection(const GridRect& a, const GridRect& b) noexcept {
  const std::int64_t i0 = std::max(a.i0, b.i0), j0 = std::max(a.j0, b.j0);
  const std::int64_t i1 = std::min(a.i1(), b.i1()), j1 = std::min(a.j1(), b.j1());
  if (i1 <= i0 || j1 <= j0) return {i0, j0, 0, 0};
  return {i0, j0, static_cast<int>(i1 - i0), static_cast<int>(j1 - j0)};
}

}  // namespace shore
