#pragma once
// The columns through which a cylinder reaches at or below a height: the window a caller
// rasterizes when only the cylinder's lower part can meet the ground (a raycast wheel's
// bottom), so the columns above that height are not computed at all.

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "shore/bullet/envelope.h"
#include "shore/core/grid_rect.h"
#include "shore/core/vec3.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

/// A rectangle of `window` holding every column whose vertical line meets the solid
/// cylinder (centre c, unit axis u, half length h, radius r, all m) at a height <= z_top:
/// every other column of `window` has its lowest point above z_top. Padded by a column on
/// every side against rounding; empty if no part of the cylinder lies that low; `window`
/// itself for an axis within 1e-6 rad of vertical (no cheap bound there).
///
/// Why it holds: write a point of the cylinder as c + a u + s e1 + t e2 with |a| <= h and
/// s^2 + t^2 <= r^2, where e1 is the up direction within the plane across the axis
/// (height g = sqrt(1 - u_z^2) per unit) and e2 = u x e1 is level. Its height is
/// c_z + a u_z + s g <= z_top, so s <= s_top = (z_top - c_z + h |u_z|) / g; where s_top < 0,
/// |t| <= sqrt(r^2 - s_top^2). The rectangle bounds |a| u + s e1 + t e2 over those ranges.
inline GridRect cylinder_window_below(const EnvelopeGrid& grid, const GridRect& window, Vec3 c, Vec3 u, double h,
                                      double r, double z_top) {
  const double g = std::sqrt(std::max(0.0, 1.0 - u.z * u.z));
  if (!(g > 1e-6)) return window;
  const double s_top = (z_top - c.z + h * std::abs(u.z)) / g;
  if (s_top < -r) return {};
  const double t_most = s_top >= 0.0 ? r : std::sqrt(std::max(0.0, r * r - s_top * s_top));
  const Vec3 e1{-u.z * u.x / g, -u.z * u.y / g, g};                      // (z - u_z u) / g
  const Vec3 e2{u.y * e1.z - u.z * e1.y, u.z * e1.x - u.x * e1.z, 0.0};  // u x e1, level
  const double ex = h * std::abs(u.x) + r * std::abs(e1.x) + t_most * std::abs(e2.x);
  const double ey = h * std::abs(u.y) + r * std::abs(e1.y) + t_most * std::abs(e2.y);
  if (!std::isfinite(ex) || !std::isfinite(ey)) return window;
  const double fi0 = std::floor((c.x - ex - grid.origin_x) / grid.cell) - 1.0;
  const double fi1 = std::ceil((c.x + ex - grid.origin_x) / grid.cell) + 1.0;
  const double fj0 = std::floor((c.y - ey - grid.origin_y) / grid.cell) - 1.0;
  const double fj1 = std::ceil((c.y + ey - grid.origin_y) / grid.cell) + 1.0;
  // Clamped to the window first: window_of's indices are within +-1e15, so these casts fit.
  const double wi0 = static_cast<double>(window.i0), wj0 = static_cast<double>(window.j0);
  const auto i0 = static_cast<std::int64_t>(std::max(fi0, wi0));
  const auto i1 = static_cast<std::int64_t>(std::min(fi1, wi0 + window.nx - 1));
  const auto j0 = static_cast<std::int64_t>(std::max(fj0, wj0));
  const auto j1 = static_cast<std::int64_t>(std::min(fj1, wj0 + window.ny - 1));
  if (i1 < i0 || j1 < j0) return {};
  return {i0, j0, static_cast<int>(i1 - i0 + 1), static_cast<int>(j1 - j0 + 1)};
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
