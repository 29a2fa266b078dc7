#pragma once
// Private: node positions read from a Field, a rectangle at a time, and the geometry the
// extractor measures with them: a triangle's linear interpolant, the distance a node lies
// from it, and the clipping of triangles to the grid's border.

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "bintree.h"
#include "shore/core/vec3.h"
#include "shore/mesh/field.h"

namespace shore::mesh::detail {

using shore::Vec3;

inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// The grid's nodes [0, ni - 1] x [0, nj - 1] (a closed box in grid coordinates).
struct Domain {
  std::int64_t ni = 0, nj = 0;
  [[nodiscard]] bool contains(Node n) const { return n.i >= 0 && n.j >= 0 && n.i < ni && n.j < nj; }
  /// True if the closed triangle lies inside the box.
  [[nodiscard]] bool holds(const Tri& t) const { return contains(t.p0) && contains(t.apex) && contains(t.p2); }
};

/// Positions of the nodes of a rectangle (clamped to the domain when read).
class Block {
 public:
  /// Reads r ∩ domain from the field; adds the count of nodes read to *counter.
  void read(const Field& field, const Domain& d, GridRect r, std::int64_t* counter);
  [[nodiscard]] bool holds(Node n) const { return r_.contains(n.i, n.j); }
  [[nodiscard]] const double* at(Node n) const { return &xyz_[3 * r_.index(n.i, n.j)]; }
  [[nodiscard]] Vec3 position(Node n) const {
    const double* p = at(n);
    return {p[0], p[1], p[2]};
  }
  [[nodiscard]] const GridRect& rect() const { return r_; }

 private:
  GridRect r_;
  std::vector<double> xyz_;
};

/// A node's position is missing (a hole) when its z is not finite.
inline bool is_hole(const double* p) { return !std::isfinite(p[2]); }

/// Distance from p to q: vertical for a height field, else 3-D.
inline double distance(const Vec3& p, const Vec3& q, bool height_field) {
  if (height_field) return std::abs(p.z - q.z);
  const double dx = p.x - q.x, dy = p.y - q.y, dz = p.z - q.z;
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}
inline double distance(const double* p, const Vec3& q, bool height_field) {
  return distance(Vec3{p[0], p[1], p[2]}, q, height_field);
}

/// The linear interpolant of a lattice triangle's corner positions, at any grid point.
class Interpolant {
 public:
  Interpolant(const std::array<Node, 3>& q, const std::array<Vec3, 3>& p);
  [[nodiscard]] Vec3 at(double i, double j) const;

 private:
  std::array<Node, 3> q_;
  std::array<Vec3, 3> p_;
  double inv_area2_ = 0.0;
};

/// Largest distance from a node inside the closed lattice triangle q (counter-clockwise,
/// corners inside the block) to the triangle's interpolant of the corners' positions;
/// +infinity if a node inside is a hole.
double lattice_error(const Block& b, const std::array<Node, 3>& q, bool height_field);

/// The triangle clipped to the domain, as a fan of lattice triangles (counter-clockwise):
/// the triangle itself when it lies inside, none when it lies outside. Every corner is a
/// node of the domain (a bintree triangle's edges cross the border at nodes). Returns how many.
int clip_to_domain(const Tri& t, const Domain& d, std::array<std::array<Node, 3>, 5>& out);

/// Error of a bintree triangle with the nodes of the block: the largest of its clipped
/// pieces' lattice_error (0 outside the domain).
double triangle_error(const Block& b, const Tri& t, const Domain& d, bool height_field);

/// Convex polygon (grid coordinates) of a triangle clipped to the closed box
/// [i0, i1] x [j0, j1]; returns the vertex count (0: no overlap).
int clip_polygon(const std::array<Node, 3>& tri, double i0, double j0, double i1, double j1,
                 std::array<std::array<double, 2>, 9>& out);

}  // namespace shore::mesh::detail
