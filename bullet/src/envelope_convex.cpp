// Analytic envelope primitives: ball, finite cylinder, box, rounded cylinder, cone.
// Each one intersects the vertical line through a column with its solid in closed form;
// only the rounded rims of margin-swept cylinders and cones (tori, a quartic) use a Newton
// iteration on the distance to the solid's core, which is convex along the line and so
// converges monotonically from outside.
#include <limits>
#include <utility>

#include "envelope_internal.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace envelope_detail {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// A line this close to parallel with a cylinder's axis (sin^2 of the angle) is treated as
// parallel: the error is below 1e-12 m for any body under a kilometre.
constexpr double kParallel = 1e-24;
// Newton stops when the line point is this close to the margin surface (m).
constexpr double kNewtonTolerance = 1e-12;
constexpr int kNewtonIterations = 100;

// The per-column interval helpers run for every column of every envelope and probe: inlined,
// so the callers keep their loop-invariant values in registers across columns (inlining
// changes no result: no contraction, the same operations in the same order).
#define SHORE_ENVELOPE_INLINE [[gnu::always_inline]] inline

/// Real roots t1 <= t2 of a t^2 + 2 b t + c = 0 (a != 0), without cancellation.
SHORE_ENVELOPE_INLINE bool quadratic_roots(double a, double b, double c, double& t1, double& t2) noexcept {
  const double disc = b * b - a * c;
  if (disc < 0) return false;
  const double q = -(b + std::copysign(std::sqrt(disc), b));
  if (q == 0) {
    t1 = t2 = 0;
    return true;
  }
  t1 = q / a;
  t2 = c / q;
  if (t1 > t2) std::swap(t1, t2);
  return true;
}

/// Narrows [lo, hi] to the parameters where o + s d lies in [-h, h].
SHORE_ENVELOPE_INLINE bool clip_slab(double o, double d, double h, double& lo, double& hi) noexcept {
  if (d == 0) return std::abs(o) <= h && lo <= hi;
  const double inv = 1.0 / d;
  double a = (-h - o) * inv;
  double b = (h - o) * inv;
  if (a > b) std::swap(a, b);
  lo = std::max(lo, a);
  hi = std::min(hi, b);
  return lo <= hi;
}

/// Finite sharp cylinder: radial condition a s^2 + 2 b s + c <= 0 (a = sin^2 of the angle
/// between line and axis), axial coordinate a0 + s da in [-h, h].
SHORE_ENVELOPE_INLINE bool cylinder_interval(double a, double b, double c, double a0, double da, double h, double& lo,
                                             double& hi) noexcept {
  lo = -kInf;
  hi = kInf;
  if (a <= kParallel) {
    if (c > 0) return false;
  } else if (!quadratic_roots(a, b, c, lo, hi)) {
    return false;
  }
  return clip_slab(a0, da, h, lo, hi);
}

/// Cone along local z, apex at z = za, radius k * (za - z), base plane z = zb.
bool cone_interval(Vec3 o, Vec3 d, double za, double zb, double k, double& lo, double& hi) noexcept {
  double slo = -kInf;
  double shi = kInf;
  if (!clip_slab(o.z - 0.5 * (za + zb), d.z, 0.5 * (za - zb), slo, shi)) return false;
  const double w = za - o.z;
  const double k2 = k * k;
  const double dr2 = d.x * d.x + d.y * d.y;
  const double a = dr2 - k2 * d.z * d.z;
  const double b = o.x * d.x + o.y * d.y + k2 * w * d.z;
  const double c = o.x * o.x + o.y * o.y - k2 * w * w;
  // The pieces of the line inside the double cone (f <= 0): an interval, or two rays (one
  // per nappe), or all of it. Clipped to the slab only the lower nappe's piece survives
  // (and at most the apex point of the other), so their hull is the answer.
  double piece_lo[2] = {-kInf, -kInf};
  double piece_hi[2] = {kInf, kInf};
  int pieces = 1;
  if (std::abs(a) <= 1e-14 * (dr2 + k2 * d.z * d.z)) {  // line parallel to a generator
    if (b == 0) {
      if (c > 0) return false;
    } else if (b > 0) {
      piece_hi[0] = -c / (2 * b);
    } else {
      piece_lo[0] = -c / (2 * b);
    }
  } else {
    double t1 = 0;
    double t2 = 0;
    const bool real = quadratic_roots(a, b, c, t1, t2);
    if (a > 0) {
      if (!real) return false;
      piece_lo[0] = t1;
      piece_hi[0] = t2;
    } else if (real) {
      piece_hi[0] = t1;
      piece_lo[1] = t2;
      pieces = 2;
    }
  }
  lo = kInf;
  hi = -kInf;
  for (int p = 0; p < pieces; ++p) {
    const double plo = std::max(piece_lo[p], slo);
    const double phi = std::min(piece_hi[p], shi);
    if (plo <= phi) {
      lo = std::min(lo, plo);
      hi = std::max(hi, phi);
    }
  }
  return lo <= hi;
}

/// Walks from s (outside the swept solid) along dir (+1 up, -1 down) to the first point
/// within margin of the core: g(s) = dist(core) - margin is convex along the line, so Newton
/// from outside never overshoots. False if the line misses (g stops decreasing above 0).
template <class Dist>
bool newton_to_surface(const Dist& dist, Vec3 o, Vec3 d, double margin, double s, double s_end, double dir,
                       double& hit) noexcept {
  for (int it = 0; it < kNewtonIterations; ++it) {
    Vec3 diff;
    const double r = dist(o + d * s, diff);
    const double g = r - margin;
    if (g <= kNewtonTolerance) {
      hit = s;
      return true;
    }
    const double slope = dir * dot(diff, d) / r;
    if (!(slope < 0)) return false;
    s -= dir * g / slope;
    if (dir * (s - s_end) > 0) return false;
  }
  return false;
}

/// Narrows [lo, hi], the line's interval through a sharp solid that contains the rounded
/// one, to the rounded solid: Newton from lo up to the entry and (upper envelope wanted)
/// from hi down to the exit. False if the line misses the rounded solid.
template <class Dist>
bool round_interval(const Dist& core_distance, Vec3 o, Vec3 d, double margin, bool upper, double& lo,
                    double& hi) noexcept {
  double entry = 0;
  if (!newton_to_surface(core_distance, o, d, margin, lo, hi, +1.0, entry)) return false;
  double exit = entry;
  if (upper && !newton_to_surface(core_distance, o, d, margin, hi, entry, -1.0, exit)) exit = entry;
  lo = entry;
  hi = exit;
  return true;
}

/// Frame whose local z is the shape's axis `up` (the other two axes are the radial ones).
Frame with_axis_as_z(const Frame& f, int up) noexcept {
  const int p = (up + 1) % 3;
  const int q = (up + 2) % 3;
  Frame g = f;
  for (int row = 0; row < 3; ++row) {
    g.r[row][0] = f.r[row][p];
    g.r[row][1] = f.r[row][q];
    g.r[row][2] = f.r[row][up];
  }
  return g;
}

/// World half extents of a cylinder along unit axis u (half length h, radius r).
Vec3 cylinder_extent(Vec3 u, double h, double r) noexcept {
  auto ext = [&](double uk) { return h * std::abs(uk) + r * std::sqrt(std::max(0.0, 1.0 - uk * uk)); };
  return {ext(u.x), ext(u.y), ext(u.z)};
}

/// Calls fn(o, d, lo, hi) for every column within ext of f.t, with the column's vertical
/// line o + s d in local coordinates (s = world z - f.t.z); merges [lo, hi] where it returns true.
template <class Fn>
void for_each_local_column(Canvas& cv, const Frame& f, Vec3 ext, Fn&& fn) {
  std::int64_t ilo = 0, ihi = 0, jlo = 0, jhi = 0;
  if (!cv.span_i(f.t.x - ext.x, f.t.x + ext.x, ilo, ihi) || !cv.span_j(f.t.y - ext.y, f.t.y + ext.y, jlo, jhi)) return;
  const Vec3 d = f.to_local_dir({0, 0, 1});
  const Vec3 step = f.to_local_dir({cv.cell(), 0, 0});
  const double x0 = cv.x(ilo) - f.t.x;
  for (std::int64_t j = jlo; j <= jhi; ++j) {
    const Vec3 row = f.to_local_dir({x0, cv.y(j) - f.t.y, 0});
    for (std::int64_t i = ilo; i <= ihi; ++i) {
      const Vec3 o = row + step * static_cast<double>(i - ilo);
      double lo = 0;
      double hi = 0;
      if (fn(o, d, lo, hi)) cv.put(i, j, f.t.z + lo, f.t.z + hi);
    }
  }
}

}  // namespace

void draw_ball(Canvas& cv, Vec3 c, double r) {
  std::int64_t ilo = 0, ihi = 0, jlo = 0, jhi = 0;
  if (!cv.span_j(c.y - r, c.y + r, jlo, jhi)) return;
  const double r2 = r * r;
  for (std::int64_t j = jlo; j <= jhi; ++j) {
    const double dy = cv.y(j) - c.y;
    const double q = r2 - dy * dy;
    if (q < 0) continue;
    const double half_row = std::sqrt(q);
    if (!cv.span_i(c.x - half_row, c.x + half_row, ilo, ihi)) continue;
    for (std::int64_t i = ilo; i <= ihi; ++i) {
      const double dx = cv.x(i) - c.x;
      const double h2 = q - dx * dx;
      if (h2 < 0) continue;
      const double half = std::sqrt(h2);
      cv.put(i, j, c.z - half, c.z + half);
    }
  }
}

namespace {

/// A cylinder whose axis is (within kParallel) upright: each column within the radius of
/// the axis holds the line's stretch inside the axial slab, a0 + s u.z in [-h, h].
void draw_upright_cylinder(Canvas& cv, Vec3 c, Vec3 u, double h, double r, std::int64_t ilo, std::int64_t ihi,
                           std::int64_t jlo, std::int64_t jhi) {
  const double r2 = r * r, inv_uz = 1.0 / u.z, h_first = u.z > 0 ? -h : h;
  for (std::int64_t j = jlo; j <= jhi; ++j) {
    const double wy = cv.y(j) - c.y;
    for (std::int64_t i = ilo; i <= ihi; ++i) {
      const double wx = cv.x(i) - c.x, a0 = wx * u.x + wy * u.y;
      if (wx * wx + wy * wy - a0 * a0 - r2 > 0) continue;
      cv.put(i, j, c.z + (h_first - a0) * inv_uz, c.z + (-h_first - a0) * inv_uz);
    }
  }
}

/// The rows of a cylinder whose axis is not upright (a = u.x^2 + u.y^2 > kParallel): the
/// line (x, y, c.z + s), w = (x - c.x, y - c.y), has the axial coordinate a0 + s u.z with
/// a0 = w . u, and its squared distance from the axis is a s^2 - 2 a0 u.z s + |w|^2 - a0^2
/// (u a unit vector, so 1 - u.z^2 = a). It is inside the radius between that quadratic's
/// roots, s = (a0 u.z -+ sqrt(D)) / a with D = a0^2 - a (|w|^2 - r^2), and inside the
/// length where the axial coordinate lies in [-h, h]: per column a few products, one
/// square root and no division. `kLevel`: u.z is 0, and a column is inside the length
/// whole or not at all.
template <bool kLevel>
void cylinder_rows(Canvas& cv, Vec3 c, Vec3 u, double h, double r, double a, std::int64_t ilo, std::int64_t ihi,
                   std::int64_t jlo, std::int64_t jhi) {
  const double inv_a = 1.0 / a, r2 = r * r, cell = cv.cell();
  // The axial slab as a range of s: (-+h - a0) / u.z, ordered by u.z's sign.
  const double inv_uz = kLevel ? 0.0 : 1.0 / u.z, h_first = u.z > 0 ? -h : h;
  const double wx0 = cv.x(ilo) - c.x;
  for (std::int64_t j = jlo; j <= jhi; ++j) {
    const double wy = cv.y(j) - c.y, off_row = wy * wy - r2, ay = wy * u.y;
    for (std::int64_t i = ilo; i <= ihi; ++i) {
      const double wx = wx0 + static_cast<double>(i - ilo) * cell;
      const double a0 = wx * u.x + ay;
      const double disc = a0 * a0 - a * (wx * wx + off_row);
      if (!(disc >= 0)) continue;
      const double root = std::sqrt(disc), b = a0 * u.z;
      double lo = (b - root) * inv_a, hi = (b + root) * inv_a;
      if constexpr (kLevel) {
        if (!(std::abs(a0) <= h)) continue;
      } else {
        lo = std::max(lo, (h_first - a0) * inv_uz);
        hi = std::min(hi, (-h_first - a0) * inv_uz);
        if (!(lo <= hi)) continue;
      }
      cv.put(i, j, c.z + lo, c.z + hi);
    }
  }
}

}  // namespace

void draw_cylinder(Canvas& cv, Vec3 c, Vec3 u, double h, double r) {
  const Vec3 ext = cylinder_extent(u, h, r);
  std::int64_t ilo = 0, ihi = 0, jlo = 0, jhi = 0;
  if (!cv.span_i(c.x - ext.x, c.x + ext.x, ilo, ihi) || !cv.span_j(c.y - ext.y, c.y + ext.y, jlo, jhi)) return;
  const double a = u.x * u.x + u.y * u.y;
  if (a <= kParallel)
    draw_upright_cylinder(cv, c, u, h, r, ilo, ihi, jlo, jhi);
  else if (u.z == 0)
    cylinder_rows<true>(cv, c, u, h, r, a, ilo, ihi, jlo, jhi);
  else
    cylinder_rows<false>(cv, c, u, h, r, a, ilo, ihi, jlo, jhi);
}

void draw_box(Canvas& cv, const Frame& f, Vec3 half) {
  Vec3 ext;
  ext.x = std::abs(f.r[0][0]) * half.x + std::abs(f.r[0][1]) * half.y + std::abs(f.r[0][2]) * half.z;
  ext.y = std::abs(f.r[1][0]) * half.x + std::abs(f.r[1][1]) * half.y + std::abs(f.r[1][2]) * half.z;
  ext.z = 0;
  for_each_local_column(cv, f, ext, [&](Vec3 o, Vec3 d, double& lo, double& hi) {
    lo = -kInf;
    hi = kInf;
    return clip_slab(o.x, d.x, half.x, lo, hi) && clip_slab(o.y, d.y, half.y, lo, hi) &&
           clip_slab(o.z, d.z, half.z, lo, hi);
  });
}

void draw_rounded_cylinder(Canvas& cv, const Frame& f, int up, double r, double h, double margin) {
  if (margin <= 0) {
    draw_cylinder(cv, f.t, f.axis(up), h, r);
    return;
  }
  const Frame g = with_axis_as_z(f, up);
  const double rc = std::max(r - margin, 0.0);
  const double hc = std::max(h - margin, 0.0);
  auto core_distance = [rc, hc](Vec3 p, Vec3& diff) {
    const double rho = std::sqrt(p.x * p.x + p.y * p.y);
    const double over = rho - rc;
    const double s = (over > 0 && rho > 0) ? over / rho : 0.0;
    const double dz = p.z > hc ? p.z - hc : (p.z < -hc ? p.z + hc : 0.0);
    diff = {p.x * s, p.y * s, dz};
    return norm(diff);
  };
  const bool upper = cv.upper();
  for_each_local_column(cv, g, cylinder_extent(g.axis(2), h, r), [&](Vec3 o, Vec3 d, double& lo, double& hi) {
    // The sharp cylinder contains the rounded one and shares its flat and curved faces:
    // start there and let Newton round the rims.
    if (!cylinder_interval(d.x * d.x + d.y * d.y, o.x * d.x + o.y * d.y, o.x * o.x + o.y * o.y - r * r, o.z, d.z, h, lo,
                           hi))
      return false;
    return round_interval(core_distance, o, d, margin, upper, lo, hi);
  });
}

void draw_cone(Canvas& cv, const Frame& f, int up, double radius, double height, double margin) {
  const Frame g = with_axis_as_z(f, up);
  const double half = 0.5 * height;
  const double k = radius / height;
  const Vec3 ext = cylinder_extent(g.axis(2), half + margin, radius + margin);
  if (margin <= 0) {
    for_each_local_column(cv, g, ext, [&](Vec3 o, Vec3 d, double& lo, double& hi) {
      return cone_interval(o, d, half, -half, k, lo, hi);
    });
    return;
  }
  // The cone swept by a ball lies inside the cone whose faces are moved out by the margin:
  // apex up by margin / sin(half angle), base down by margin. Start there, Newton rounds
  // the apex and the base rim.
  const double sin_half_angle = radius / std::sqrt(radius * radius + height * height);
  const double apex = half + margin / sin_half_angle;
  const double base = -half - margin;
  auto core_distance = [radius, height, half](Vec3 p, Vec3& diff) {
    const double rho = std::sqrt(p.x * p.x + p.y * p.y);
    if (p.z >= -half && p.z <= half && rho * height <= radius * (half - p.z)) {
      diff = {};
      return 0.0;
    }
    // Nearest point in the meridian half-plane: on the base segment or the slanted side.
    const double base_dr = rho - std::min(rho, radius);
    const double base_dz = p.z + half;
    const double ex = radius;
    const double ey = -height;
    const double tau = std::clamp((rho * ex + (p.z - half) * ey) / (ex * ex + ey * ey), 0.0, 1.0);
    const double side_dr = rho - tau * radius;
    const double side_dz = p.z - (half - tau * height);
    double dr = base_dr;
    double dz = base_dz;
    if (side_dr * side_dr + side_dz * side_dz < base_dr * base_dr + base_dz * base_dz) {
      dr = side_dr;
      dz = side_dz;
    }
    const double s = rho > 0 ? dr / rho : 0.0;
    diff = {p.x * s, p.y * s, dz};
    return norm(diff);
  };
  const bool upper = cv.upper();
  for_each_local_column(cv, g, ext, [&](Vec3 o, Vec3 d, double& lo, double& hi) {
    return cone_interval(o, d, apex, base, k, lo, hi) && round_interval(core_distance, o, d, margin, upper, lo, hi);
  });
}

}  // namespace envelope_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
