#pragma once
// Checks of a mesh against the grid it was made from, independent of how it was made:
// every node's distance to the mesh (found by locating the node in the mesh's triangles in
// grid space), the projected size of that distance from a camera, and the mesh's topology
// (edge-manifold, consistent winding, no T-junctions, an exact cover of the grid).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <numeric>
#include <set>
#include <string>
#include <vector>

#include "shore/mesh/chunked_mesh.h"

namespace shore::mesh::testing {

/// A field given by a function of the node: z(i, j) on a regular grid (height field), or a
/// full position; optionally with a base plane and changes reported by the test.
class FunctionField : public Field {
 public:
  using Position = std::function<std::array<double, 3>(std::int64_t, std::int64_t)>;
  FunctionField(std::int64_t ni, std::int64_t nj, Position p, bool height_field)
      : ni_(ni), nj_(nj), p_(std::move(p)), height_field_(height_field) {}
  /// A height field with cell h: node (i, j) at (x0 + i h, y0 + j h, z(i, j)).
  static FunctionField heights(std::int64_t ni, std::int64_t nj, double h,
                               std::function<double(std::int64_t, std::int64_t)> z, double x0 = 0.0, double y0 = 0.0) {
    return FunctionField(
        ni, nj,
        [=](std::int64_t i, std::int64_t j) {
          return std::array<double, 3>{x0 + i * h, y0 + j * h, z(i, j)};
        },
        true);
  }
  [[nodiscard]] std::int64_t ni() const override { return ni_; }
  [[nodiscard]] std::int64_t nj() const override { return nj_; }
  [[nodiscard]] bool height_field() const override { return height_field_; }
  void positions(const GridRect& r, std::span<double> out) const override {
    std::size_t k = 0;
    for (std::int64_t j = r.j0; j < r.j0 + r.ny; ++j)
      for (std::int64_t i = r.i0; i < r.i0 + r.nx; ++i) {
        ++reads;
        const std::array<double, 3> p = p_(i, j);
        out[k++] = p[0], out[k++] = p[1], out[k++] = p[2];
      }
  }
  [[nodiscard]] std::optional<BasePlane> base() const override { return base_; }
  void take_changes(std::vector<GridRect>& out) override {
    out = pending_;
    pending_.clear();
  }
  std::array<double, 3> at(std::int64_t i, std::int64_t j) const { return p_(i, j); }

  void set_base(BasePlane b) { base_ = b; }
  void set(Position p) { p_ = std::move(p); }
  void report(GridRect r) { pending_.push_back(r); }
  mutable std::int64_t reads = 0;

 private:
  std::int64_t ni_, nj_;
  Position p_;
  bool height_field_;
  std::optional<BasePlane> base_;
  std::vector<GridRect> pending_;
};

struct GridNode {
  std::int64_t i, j;
};

inline GridNode node_of(std::uint64_t id, std::int64_t ni) {
  return {static_cast<std::int64_t>(id % static_cast<std::uint64_t>(ni)),
          static_cast<std::int64_t>(id / static_cast<std::uint64_t>(ni))};
}

inline std::int64_t cross(GridNode a, GridNode b, GridNode c) {
  return (b.i - a.i) * (c.j - a.j) - (b.j - a.j) * (c.i - a.i);
}

/// Positions of the nodes a set of triangles touches and of a window, read once.
class PositionCache {
 public:
  explicit PositionCache(const Field& f) : f_(f) {}
  const double* at(GridNode n) {
    auto [it, fresh] = cache_.try_emplace(static_cast<std::uint64_t>(n.j * f_.ni() + n.i));
    if (fresh) f_.positions({n.i, n.j, 1, 1}, it->second);
    return it->second.data();
  }

 private:
  const Field& f_;
  std::map<std::uint64_t, std::array<double, 3>> cache_;
};

/// Locates every node of the window (default: the whole grid) in the merged mesh's
/// triangles (grid space) and calls measure(node position, mesh point at the node's grid
/// coordinates); returns, per window node (row by row), the largest value measure gave, or -1
/// where no triangle covers the node. Positions come from the field itself (double).
template <class Measure>
std::vector<double> per_node(const TriangleMesh& m, const Field& f, GridRect w, Measure&& measure) {
  const std::int64_t ni = f.ni();
  if (w.nx == 0) w = {0, 0, static_cast<int>(f.ni()), static_cast<int>(f.nj())};
  std::vector<double> out(w.size(), -1.0);
  PositionCache cache(f);
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const GridNode a = node_of(m.nodes[m.indices[3 * t]], ni), b = node_of(m.nodes[m.indices[3 * t + 1]], ni),
                   c = node_of(m.nodes[m.indices[3 * t + 2]], ni);
    const double area = static_cast<double>(cross(a, b, c));
    const std::int64_t i0 = std::max(w.i0, std::min({a.i, b.i, c.i})),
                       i1 = std::min(w.i0 + w.nx - 1, std::max({a.i, b.i, c.i}));
    const std::int64_t j0 = std::max(w.j0, std::min({a.j, b.j, c.j})),
                       j1 = std::min(w.j0 + w.ny - 1, std::max({a.j, b.j, c.j}));
    for (std::int64_t j = j0; j <= j1; ++j)
      for (std::int64_t i = i0; i <= i1; ++i) {
        const GridNode x{i, j};
        const std::int64_t wa = cross(b, c, x), wb = cross(c, a, x), wc = cross(a, b, x);
        if (wa < 0 || wb < 0 || wc < 0) continue;
        std::array<double, 3> p{}, l{};
        for (std::size_t k = 0; k < 3; ++k) {
          p[k] = cache.at(x)[k];
          l[k] = (static_cast<double>(wa) * cache.at(a)[k] + static_cast<double>(wb) * cache.at(b)[k] +
                  static_cast<double>(wc) * cache.at(c)[k]) /
                 area;
        }
        if (f.height_field()) l[0] = p[0], l[1] = p[1];  // the grid's x and y: only z is interpolated
        double& e = out[static_cast<std::size_t>((j - w.j0) * w.nx + (i - w.i0))];
        e = std::max(e, measure(p, l));
      }
  }
  return out;
}

/// Per node: the distance from its position to the mesh point at its grid coordinates
/// (vertical for a height field, else 3-D), or -1 if uncovered.
inline std::vector<double> node_errors(const TriangleMesh& m, const Field& f, GridRect w = {}) {
  return per_node(m, f, w, [](const std::array<double, 3>& p, const std::array<double, 3>& l) {
    return std::sqrt((p[0] - l[0]) * (p[0] - l[0]) + (p[1] - l[1]) * (p[1] - l[1]) + (p[2] - l[2]) * (p[2] - l[2]));
  });
}

/// Per node: the angle (rad) the segment from its position to that mesh point subtends at
/// the eye, or -1 if uncovered.
inline std::vector<double> node_angles(const TriangleMesh& m, const Field& f, const Camera& cam, GridRect w = {}) {
  return per_node(m, f, w, [&](const std::array<double, 3>& p, const std::array<double, 3>& l) {
    const Vec3& c = cam.position;
    const std::array<double, 3> u{p[0] - c.x, p[1] - c.y, p[2] - c.z}, v{l[0] - c.x, l[1] - c.y, l[2] - c.z};
    const std::array<double, 3> uv{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    return std::atan2(std::sqrt(uv[0] * uv[0] + uv[1] * uv[1] + uv[2] * uv[2]),
                      u[0] * v[0] + u[1] * v[1] + u[2] * v[2]);
  });
}

/// Topology failures of a mesh over an ni x nj grid (empty: none): every triangle counter-
/// clockwise in grid space, every edge in at most two triangles and then in opposite
/// directions, edges in one triangle only along the grid's border (unless holes are
/// allowed), no vertex inside another triangle's edge, and the triangles' grid areas
/// adding up to the grid's (an exact cover) unless holes are allowed.
inline std::vector<std::string> topology_failures(const TriangleMesh& m, std::int64_t ni, std::int64_t nj,
                                                  bool holes_allowed = false) {
  std::vector<std::string> bad;
  auto note = [&](const std::string& s) {
    if (bad.size() < 20) bad.push_back(s);
  };
  std::map<std::pair<std::uint64_t, std::uint64_t>, int> directed;
  std::int64_t area2 = 0;
  std::set<std::uint64_t> vertices(m.nodes.begin(), m.nodes.end());
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const std::array<std::uint64_t, 3> v{m.nodes[m.indices[3 * t]], m.nodes[m.indices[3 * t + 1]],
                                         m.nodes[m.indices[3 * t + 2]]};
    const std::int64_t a = cross(node_of(v[0], ni), node_of(v[1], ni), node_of(v[2], ni));
    if (a <= 0) note("triangle " + std::to_string(t) + " is not counter-clockwise in grid space");
    area2 += a;
    for (int e = 0; e < 3; ++e) ++directed[{v[static_cast<std::size_t>(e)], v[static_cast<std::size_t>((e + 1) % 3)]}];
  }
  if (!holes_allowed && area2 != 2 * (ni - 1) * (nj - 1))
    note("grid area covered " + std::to_string(area2) + " / 2, grid " + std::to_string(2 * (ni - 1) * (nj - 1)) +
         " / 2");
  auto on_border = [&](GridNode a, GridNode b) {
    return (a.i == b.i && (a.i == 0 || a.i == ni - 1)) || (a.j == b.j && (a.j == 0 || a.j == nj - 1));
  };
  for (const auto& [edge, count] : directed) {
    if (count > 1) note("edge used twice in the same direction");
    const GridNode a = node_of(edge.first, ni), b = node_of(edge.second, ni);
    const auto back = directed.find({edge.second, edge.first});
    if (back == directed.end() && !holes_allowed && !on_border(a, b))
      note("open edge inside the grid: (" + std::to_string(a.i) + "," + std::to_string(a.j) + ")-(" +
           std::to_string(b.i) + "," + std::to_string(b.j) + ")");
    // No mesh vertex strictly inside the edge (a T-junction: a crack in waiting).
    const std::int64_t g = std::gcd(std::abs(b.i - a.i), std::abs(b.j - a.j));
    for (std::int64_t k = 1; k < g; ++k) {
      const GridNode x{a.i + (b.i - a.i) / g * k, a.j + (b.j - a.j) / g * k};
      if (vertices.count(static_cast<std::uint64_t>(x.j * ni + x.i)))
        note("T-junction: vertex (" + std::to_string(x.i) + "," + std::to_string(x.j) + ") inside an edge");
    }
  }
  return bad;
}

/// Applies the updates a renderer would (upload changed, drop removed) to a copy.
inline void apply(std::map<ChunkKey, Chunk>& copy, const ChunkedMesh& mesh, const MeshUpdate& u) {
  for (const ChunkKey& k : u.removed) copy.erase(k);
  for (const ChunkKey& k : u.changed) copy[k] = mesh.chunks().at(k);
}

}  // namespace shore::mesh::testing
