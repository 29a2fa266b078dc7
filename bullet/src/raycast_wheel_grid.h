#pragma once
// Internal: the grid arithmetic a raycast wheel's per-column loops repeat thousands of times
// a substep (raycast_wheels.cpp), made cheap and kept bit for bit what it replaces.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "shore/core/det_math.h"
#include "shore/core/grid_rect.h"
#include "shore/terrain/terrain.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

/// Where a rectangle's columns lie from a point, m: Terrain::column_x(i) - x for each i of
/// the rectangle and Terrain::column_y(j) - y for each j, read once (column_x is a call into
/// the terrain) and then looked up. Valid for columns of the rectangle read.
class ColumnOffsets {
 public:
  void read(const terrain::Terrain& terrain, const GridRect& rect, double x, double y) {
    i0_ = rect.i0, j0_ = rect.j0;
    dx_.resize(static_cast<std::size_t>(rect.nx));
    dy_.resize(static_cast<std::size_t>(rect.ny));
    for (int a = 0; a < rect.nx; ++a) dx_[static_cast<std::size_t>(a)] = terrain.column_x(rect.i0 + a) - x;
    for (int b = 0; b < rect.ny; ++b) dy_[static_cast<std::size_t>(b)] = terrain.column_y(rect.j0 + b) - y;
  }
  [[nodiscard]] double dx(std::int64_t i) const { return dx_[static_cast<std::size_t>(i - i0_)]; }
  [[nodiscard]] double dy(std::int64_t j) const { return dy_[static_cast<std::size_t>(j - j0_)]; }

 private:
  std::int64_t i0_ = 0, j0_ = 0;
  std::vector<double> dx_, dy_;
};

/// std::lround(x) (halves away from zero) for |x| < 2^31, inline: the library call cost more
/// than the loops' arithmetic. x - trunc(x) is exact, so the answer is lround's.
inline long round_half_away(double x) {
  const auto t = static_cast<long>(x);
  const double rest = x - static_cast<double>(t);
  return rest >= 0.5 ? t + 1 : rest <= -0.5 ? t - 1 : t;
}

/// std::floor(x) for |x| < 2^62, inline (floor is a library call without SSE4.1).
inline double floor_small(double x) {
  const auto t = static_cast<double>(static_cast<std::int64_t>(x));
  return t > x ? t - 1.0 : t;
}

/// rad, the rim angle (from the bottom, positive ahead) of a point s m ahead of a wheel's
/// centre, |s| limited to 0.95 of the radius as the rim's strips take it.
inline double rim_angle(double s, double radius) {
  const double reach = 0.95 * radius;
  s = std::clamp(s, -reach, reach);
  return det::atan2(s, std::sqrt(radius * radius - s * s));
}

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
