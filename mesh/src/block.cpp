#include "block.h"

#include <algorithm>

#include "shore/core/error.h"
#include "shore/core/floor_div.h"

namespace shore::mesh::detail {
namespace {

/// a / b rounded up (b != 0).
std::int64_t ceil_div(std::int64_t a, std::int64_t b) { return -floor_div(-a, b); }

/// Columns [lo, hi] of row j inside the closed counter-clockwise lattice triangle q.
bool row_span(const std::array<Node, 3>& q, std::int64_t j, std::int64_t& lo, std::int64_t& hi) {
  lo = std::numeric_limits<std::int64_t>::min();
  hi = std::numeric_limits<std::int64_t>::max();
  for (int e = 0; e < 3; ++e) {
    const Node a = q[static_cast<std::size_t>(e)], b = q[static_cast<std::size_t>((e + 1) % 3)];
    // Left of a -> b: (b.i - a.i)(j - a.j) - (b.j - a.j)(i - a.i) >= 0, i.e. c - s i >= 0.
    const std::int64_t s = b.j - a.j, c = (b.i - a.i) * (j - a.j) + s * a.i;
    if (s > 0)
      hi = std::min(hi, floor_div(c, s));
    else if (s < 0)
      lo = std::max(lo, ceil_div(c, s));
    else if (c < 0)
      return false;
  }
  return lo <= hi;
}

}  // namespace

void Block::read(const Field& field, const Domain& d, GridRect r, std::int64_t* counter) {
  const std::int64_t i1 = std::min(r.i0 + r.nx, d.ni), j1 = std::min(r.j0 + r.ny, d.nj);
  r.i0 = std::max<std::int64_t>(r.i0, 0), r.j0 = std::max<std::int64_t>(r.j0, 0);
  r.nx = static_cast<int>(std::max<std::int64_t>(i1 - r.i0, 0)),
  r.ny = static_cast<int>(std::max<std::int64_t>(j1 - r.j0, 0));
  r_ = r;
  xyz_.assign(3 * r.size(), 0.0);
  if (r.nx > 0 && r.ny > 0) field.positions(r, xyz_);
  if (counter) *counter += static_cast<std::int64_t>(r.size());
}

Interpolant::Interpolant(const std::array<Node, 3>& q, const std::array<Vec3, 3>& p) : q_(q), p_(p) {
  inv_area2_ = 1.0 / static_cast<double>(cross(q[0], q[1], q[2]));
}

Vec3 Interpolant::at(double i, double j) const {
  auto edge = [&](Node a, Node b) {
    return (static_cast<double>(b.i - a.i) * (j - static_cast<double>(a.j)) -
            static_cast<double>(b.j - a.j) * (i - static_cast<double>(a.i))) *
           inv_area2_;
  };
  const double w0 = edge(q_[1], q_[2]), w1 = edge(q_[2], q_[0]), w2 = edge(q_[0], q_[1]);
  Vec3 out;
  for (int k = 0; k < 3; ++k)
    out[static_cast<std::size_t>(k)] = w0 * p_[0][static_cast<std::size_t>(k)] +
                                       w1 * p_[1][static_cast<std::size_t>(k)] +
                                       w2 * p_[2][static_cast<std::size_t>(k)];
  return out;
}

double lattice_error(const Block& b, const std::array<Node, 3>& q, bool height_field) {
  const std::array<const double*, 3> c{b.at(q[0]), b.at(q[1]), b.at(q[2])};
  if (is_hole(c[0]) || is_hole(c[1]) || is_hole(c[2])) return kInf;
  const double inv = 1.0 / static_cast<double>(cross(q[0], q[1], q[2]));
  // Barycentric weight k is the edge function opposite corner k over twice the area: affine
  // in i along a row, so the interpolant is its value at the row's first node plus a step.
  std::array<double, 3> step{};
  for (std::size_t k = 0; k < 3; ++k)
    for (std::size_t e = 0; e < 3; ++e) {
      const Node a = q[(e + 1) % 3], d = q[(e + 2) % 3];
      step[k] -= static_cast<double>(d.j - a.j) * inv * c[e][k];
    }
  const std::size_t first = height_field ? 2 : 0;
  const std::int64_t j0 = std::min({q[0].j, q[1].j, q[2].j}), j1 = std::max({q[0].j, q[1].j, q[2].j});
  double worst2 = 0.0;
  for (std::int64_t j = j0; j <= j1; ++j) {
    std::int64_t lo = 0, hi = 0;
    if (!row_span(q, j, lo, hi)) continue;
    const Node start{lo, j};
    const std::array<double, 3> w{static_cast<double>(cross(q[1], q[2], start)) * inv,
                                  static_cast<double>(cross(q[2], q[0], start)) * inv,
                                  static_cast<double>(cross(q[0], q[1], start)) * inv};
    std::array<double, 3> l0{};
    for (std::size_t k = first; k < 3; ++k) l0[k] = w[0] * c[0][k] + w[1] * c[1][k] + w[2] * c[2][k];
    const double* p = b.at(start);
    for (std::int64_t n = 0; n <= hi - lo; ++n, p += 3) {
      if (is_hole(p)) return kInf;
      double d2 = 0.0;
      for (std::size_t k = first; k < 3; ++k) {
        const double d = p[k] - (l0[k] + static_cast<double>(n) * step[k]);
        d2 += d * d;
      }
      worst2 = std::max(worst2, d2);
    }
  }
  return std::sqrt(worst2);
}

int clip_polygon(const std::array<Node, 3>& tri, double i0, double j0, double i1, double j1,
                 std::array<std::array<double, 2>, 9>& out) {
  std::array<std::array<double, 2>, 9> a, b;
  int n = 3;
  for (int k = 0; k < 3; ++k)
    a[static_cast<std::size_t>(k)] = {static_cast<double>(tri[static_cast<std::size_t>(k)].i),
                                      static_cast<double>(tri[static_cast<std::size_t>(k)].j)};
  // Sutherland-Hodgman against i >= i0, i <= i1, j >= j0, j <= j1.
  for (int plane = 0; plane < 4 && n > 0; ++plane) {
    const int axis = plane / 2;
    const double bound = plane == 0 ? i0 : plane == 1 ? i1 : plane == 2 ? j0 : j1;
    const double sign = plane % 2 == 0 ? 1.0 : -1.0;  // inside: sign (x - bound) >= 0
    int m = 0;
    for (int k = 0; k < n; ++k) {
      const auto& p = a[static_cast<std::size_t>(k)];
      const auto& q = a[static_cast<std::size_t>((k + 1) % n)];
      const double dp = sign * (p[static_cast<std::size_t>(axis)] - bound);
      const double dq = sign * (q[static_cast<std::size_t>(axis)] - bound);
      if (dp >= 0) b[static_cast<std::size_t>(m++)] = p;
      if ((dp >= 0) != (dq >= 0) && dp != 0 && dq != 0) {
        const double s = dp / (dp - dq);
        std::array<double, 2> x{p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])};
        x[static_cast<std::size_t>(axis)] = bound;  // exactly on the line
        b[static_cast<std::size_t>(m++)] = x;
      }
    }
    n = m;
    a = b;
  }
  out = a;
  return n;
}

int clip_to_domain(const Tri& t, const Domain& d, std::array<std::array<Node, 3>, 5>& out) {
  if (d.holds(t)) {
    out[0] = {t.p0, t.apex, t.p2};
    return 1;
  }
  std::array<std::array<double, 2>, 9> poly;
  const int n =
      clip_polygon({t.p0, t.apex, t.p2}, 0.0, 0.0, static_cast<double>(d.ni - 1), static_cast<double>(d.nj - 1), poly);
  // The crossings of axis-parallel and diagonal edges with grid lines are nodes; drop
  // repeated and collinear points so no piece is degenerate.
  std::array<Node, 9> v;
  int m = 0;
  for (int k = 0; k < n; ++k) {
    const Node x{std::llround(poly[static_cast<std::size_t>(k)][0]),
                 std::llround(poly[static_cast<std::size_t>(k)][1])};
    if (m == 0 || !(v[static_cast<std::size_t>(m - 1)] == x)) v[static_cast<std::size_t>(m++)] = x;
  }
  while (m > 1 && v[0] == v[static_cast<std::size_t>(m - 1)]) --m;
  for (bool removed = true; removed && m >= 3;) {
    removed = false;
    for (int k = 0; k < m; ++k) {
      const Node a = v[static_cast<std::size_t>((k + m - 1) % m)], b = v[static_cast<std::size_t>(k)],
                 c = v[static_cast<std::size_t>((k + 1) % m)];
      if (cross(a, b, c) == 0) {
        std::copy(v.begin() + k + 1, v.begin() + m, v.begin() + k);
        --m;
        removed = true;
        break;
      }
    }
  }
  if (m < 3) return 0;
  for (int k = 1; k + 1 < m; ++k)
    out[static_cast<std::size_t>(k - 1)] = {v[0], v[static_cast<std::size_t>(k)], v[static_cast<std::size_t>(k + 1)]};
  return m - 2;
}

namespace {

/// Distance of the node at the middle of a lattice segment from the segment's midpoint.
double midpoint_error(const Block& b, Node a, Node c, bool height_field) {
  const double* pa = b.at(a);
  const double* pc = b.at(c);
  const double* pm = b.at({(a.i + c.i) / 2, (a.j + c.j) / 2});
  if (is_hole(pa) || is_hole(pc) || is_hole(pm)) return kInf;
  return distance(pm, {0.5 * (pa[0] + pc[0]), 0.5 * (pa[1] + pc[1]), 0.5 * (pa[2] + pc[2])}, height_field);
}

}  // namespace

double triangle_error(const Block& b, const Tri& t, const Domain& d, bool height_field) {
  // The two smallest triangles that hold more than their corners (two thirds of all
  // triangles) in closed form: their other nodes are midpoints of their edges.
  if (d.holds(t) && detail::square_side(t) == 2) {
    if (std::llabs(t.p2.i - t.p0.i) == std::llabs(t.p2.j - t.p0.j))  // legs of 2: three edge midpoints
      return std::max({midpoint_error(b, t.p0, t.p2, height_field), midpoint_error(b, t.p0, t.apex, height_field),
                       midpoint_error(b, t.apex, t.p2, height_field)});
    return midpoint_error(b, t.p0, t.p2, height_field);  // hypotenuse of 2: its midpoint
  }
  std::array<std::array<Node, 3>, 5> pieces;
  const int n = clip_to_domain(t, d, pieces);
  double worst = 0.0;
  for (int k = 0; k < n; ++k)
    worst = std::max(worst, lattice_error(b, pieces[static_cast<std::size_t>(k)], height_field));
  return worst;
}

}  // namespace shore::mesh::detail
