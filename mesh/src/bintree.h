#pragma once
// Private: the right-triangle bisection tree over a root square of S x S grid cells
// (S a power of two), in grid coordinates. docs/mesh.md draws it.
//
// A triangle is a right isosceles triangle with corners on grid nodes, stored counter-
// clockwise with its right angle (the apex) in the middle: {p0, apex, p2}, hypotenuse
// p0-p2. Splitting it at the hypotenuse's midpoint m (its split vertex) gives
// {apex, m, p0} and {p2, m, apex}. The two triangles of the root square are the diamond
// of its centre; every node but the root corners is the split vertex of exactly one
// diamond (two triangles sharing a hypotenuse, one at the root's border), and it is one of:
//   a centre: of a square of side 2t, t = the lowest set bit of (i | j), i/t and j/t odd;
//             its diamond is that square, cut along the diagonal through the centre of the
//             square of side 4t it is a quarter of;
//   an edge:  the midpoint of a side of length 2t of such squares (one of i/t, j/t odd);
//             its diamond is the two quarters of the squares on both sides of that side.
// A vertex's children are the split vertices of the triangles its split creates; a
// triangle exists in the mesh iff the split vertices of all its ancestors are active, and
// activity is saturated (a parent is active when a child is), so both triangles of a
// diamond always split together: no cracks and no T-junctions.

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>

namespace shore::mesh::detail {

struct Node {
  std::int64_t i = 0, j = 0;
  friend bool operator==(const Node&, const Node&) = default;
};

inline Node operator+(Node a, Node b) { return {a.i + b.i, a.j + b.j}; }
inline Node operator-(Node a, Node b) { return {a.i - b.i, a.j - b.j}; }

/// Twice the signed area of (a, b, c): > 0 when counter-clockwise.
inline std::int64_t cross(Node a, Node b, Node c) { return (b.i - a.i) * (c.j - a.j) - (b.j - a.j) * (c.i - a.i); }

struct Tri {
  Node p0, apex, p2;  ///< counter-clockwise; the right angle at apex; hypotenuse p0-p2
  friend bool operator==(const Tri&, const Tri&) = default;
};

/// The hypotenuse's midpoint, if it is a grid node (not for triangles of one cell).
inline bool has_split(const Tri& t) { return ((t.p0.i + t.p2.i) & 1) == 0 && ((t.p0.j + t.p2.j) & 1) == 0; }
inline Node split_vertex(const Tri& t) { return {(t.p0.i + t.p2.i) / 2, (t.p0.j + t.p2.j) / 2}; }
inline Tri first_child(const Tri& t, Node m) { return {t.apex, m, t.p0}; }
inline Tri second_child(const Tri& t, Node m) { return {t.p2, m, t.apex}; }

/// Which of its split vertex's two diamond triangles t is (0 or 1): its apex lies on
/// opposite sides of the hypotenuse.
inline int diamond_side(const Tri& t, Node m) {
  const Node d = t.apex - m;
  return (d.i > 0 || (d.i == 0 && d.j > 0)) ? 1 : 0;
}

/// Side of the square the triangle is half of (hypotenuse along a diagonal) or a quarter of
/// (hypotenuse along an axis): the chunk or larger square it belongs to.
inline std::int64_t square_side(const Tri& t) {
  const std::int64_t di = std::llabs(t.p2.i - t.p0.i), dj = std::llabs(t.p2.j - t.p0.j);
  return di == dj ? di : di + dj;
}

/// Lower-left node of that square (squares of side s are aligned to multiples of s).
inline Node square_origin(const Tri& t, std::int64_t side) {
  const std::int64_t i = std::min({t.p0.i, t.apex.i, t.p2.i}), j = std::min({t.p0.j, t.apex.j, t.p2.j});
  return {i / side * side, j / side * side};
}

enum class Kind : std::uint8_t { corner, centre, edge_i, edge_j };

/// A vertex's kind and t (centre of a square of side 2t, or edge of half-length t; an edge_i
/// vertex's hypotenuse runs along i). Root corners (and nodes outside) are `corner`.
struct VertexClass {
  Kind kind = Kind::corner;
  std::int64_t t = 0;
  /// Orders the saturation: children always have a lower rank than their parents.
  [[nodiscard]] int rank() const {
    int lg = 0;
    while ((std::int64_t{1} << lg) < t) ++lg;
    return kind == Kind::centre ? 2 * lg + 1 : 2 * lg;
  }
};

inline VertexClass classify(Node n, std::int64_t root) {
  const std::int64_t bits = n.i | n.j;
  if (n.i < 0 || n.j < 0 || n.i > root || n.j > root || bits == 0) return {};
  const std::int64_t t = bits & -bits;
  if (t >= root) return {};
  const bool i_odd = (n.i / t) & 1, j_odd = (n.j / t) & 1;
  if (i_odd && j_odd) return {Kind::centre, t};
  return {i_odd ? Kind::edge_i : Kind::edge_j, t};
}

inline bool in_root(Node n, std::int64_t root) { return n.i >= 0 && n.j >= 0 && n.i <= root && n.j <= root; }

/// The diamond's triangles of a vertex (1 at the root's border, else 2), counter-clockwise
/// with the apex in the middle, side 0 first. Returns how many.
inline int diamond(Node v, std::int64_t root, std::array<Tri, 2>& out) {
  const VertexClass c = classify(v, root);
  const std::int64_t t = c.t;
  Node h0, h1, a0, a1;  // hypotenuse ends and the two apexes
  switch (c.kind) {
    case Kind::corner:
      return 0;
    case Kind::centre: {
      // The diagonal runs through the centre of the square of side 4t this one is a
      // quarter of: the corner whose coordinates are odd multiples of 2t.
      const std::int64_t si = ((v.i + t) / (2 * t)) & 1 ? 1 : -1, sj = ((v.j + t) / (2 * t)) & 1 ? 1 : -1;
      h0 = {v.i + si * t, v.j + sj * t}, h1 = {v.i - si * t, v.j - sj * t};
      a0 = {v.i + si * t, v.j - sj * t}, a1 = {v.i - si * t, v.j + sj * t};
      break;
    }
    case Kind::edge_i:
      h0 = {v.i - t, v.j}, h1 = {v.i + t, v.j}, a0 = {v.i, v.j - t}, a1 = {v.i, v.j + t};
      break;
    case Kind::edge_j:
      h0 = {v.i, v.j - t}, h1 = {v.i, v.j + t}, a0 = {v.i - t, v.j}, a1 = {v.i + t, v.j};
      break;
  }
  int n = 0;
  std::array<Tri, 2> found;
  for (const Node a : {a0, a1}) {
    if (!in_root(a, root)) continue;
    Tri tri{h0, a, h1};
    if (cross(tri.p0, tri.apex, tri.p2) < 0) std::swap(tri.p0, tri.p2);
    found[static_cast<std::size_t>(n++)] = tri;
  }
  if (n == 2 && diamond_side(found[0], v) == 1) std::swap(found[0], found[1]);
  for (int k = 0; k < n; ++k) out[static_cast<std::size_t>(k)] = found[static_cast<std::size_t>(k)];
  return n;
}

/// The vertex's children (the split vertices one level down) inside the root; returns how many.
inline int children(Node v, std::int64_t root, std::array<Node, 4>& out) {
  const VertexClass c = classify(v, root);
  const std::int64_t t = c.t;
  int n = 0;
  auto add = [&](Node x) {
    if (in_root(x, root)) out[static_cast<std::size_t>(n++)] = x;
  };
  if (c.kind == Kind::centre) {
    add({v.i - t, v.j}), add({v.i + t, v.j}), add({v.i, v.j - t}), add({v.i, v.j + t});
  } else if (c.kind != Kind::corner && t >= 2) {
    const std::int64_t h = t / 2;
    add({v.i - h, v.j - h}), add({v.i + h, v.j - h}), add({v.i - h, v.j + h}), add({v.i + h, v.j + h});
  }
  return n;
}

/// The vertex's parents (the apexes of its diamond's triangles) that are vertices.
inline int parents(Node v, std::int64_t root, std::array<Node, 2>& out) {
  std::array<Tri, 2> tris;
  const int k = diamond(v, root, tris);
  int n = 0;
  for (int q = 0; q < k; ++q)
    if (classify(tris[static_cast<std::size_t>(q)].apex, root).kind != Kind::corner)
      out[static_cast<std::size_t>(n++)] = tris[static_cast<std::size_t>(q)].apex;
  return n;
}

}  // namespace shore::mesh::detail
