#pragma once
// What the mesh extractor reads: a surface sampled at the nodes of a regular grid. The soil
// (one node per column, shore/terrain/mesh_field.h) and the water (one node per spring-mass
// node, with its 3-D position, shore/water/mesh_field.h) both adapt to it, so one extractor
// (shore/mesh/chunked_mesh.h) serves both.
//
// Node (i, j), i in [0, ni), j in [0, nj), is joined to the nodes next to it in (i, j):
// triangles are built in grid space and take the nodes' 3-D positions, so a surface whose
// nodes drift sideways or fold over (a steep water wave) keeps its shape.

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "shore/core/grid_rect.h"
#include "shore/core/vec3.h"

namespace shore::mesh {

/// An affine map of the grid: node (i, j) at origin + i di + j dj (m).
struct BasePlane {
  Vec3 origin{};
  Vec3 di{};
  Vec3 dj{};
  /// The position of node (i, j), computed the way the extractor computes it.
  [[nodiscard]] Vec3 at(double i, double j) const {
    return {origin[0] + i * di[0] + j * dj[0], origin[1] + i * di[1] + j * dj[1], origin[2] + i * di[2] + j * dj[2]};
  }
};

class Field {
 public:
  virtual ~Field() = default;

  /// Nodes along i and along j, each >= 2, fixed for the field's life.
  [[nodiscard]] virtual std::int64_t ni() const = 0;
  [[nodiscard]] virtual std::int64_t nj() const = 0;
  /// True if every node's x and y are an affine map of (i, j) and only z varies (a height
  /// field: ground). Errors are then vertical distances; otherwise 3-D distances.
  [[nodiscard]] virtual bool height_field() const = 0;
  /// World positions (m) of the nodes of r, which lies inside the grid: x, y, z per node,
  /// row by row (node (r.i0 + a, r.j0 + b) at 3 (b r.nx + a)); out.size() == 3 r.size().
  /// A NaN z marks a missing node (a hole): no triangle touches it.
  virtual void positions(const GridRect& r, std::span<double> out) const = 0;
  /// The plane every node lies on exactly until take_changes reports it (untouched flat
  /// ground, water at rest), if there is one. With it, nodes never reported are never read:
  /// a large field costs what its changed parts cost. Without it, every node is read.
  [[nodiscard]] virtual std::optional<BasePlane> base() const { return std::nullopt; }
  /// Rectangles (inside the grid) covering every node whose position changed since the
  /// previous call. The first call covers every node that may lie off base(): the whole
  /// grid if there is no base.
  virtual void take_changes(std::vector<GridRect>& out) = 0;
};

}  // namespace shore::mesh
