#pragma once
// Envelope rasterization: the lowest (and optionally highest) point of a Bullet collision
// shape on the vertical line through every column of the terrain / water grid.
//
// This replaces one ray cast per column. It is exact: every shape is intersected with the
// vertical line in closed form (sphere, box, capsule, cylinder, cone), by triangle
// rasterization with the plane of each triangle (convex hulls, triangle meshes), or, only
// where a collision margin rounds an edge, by a monotone Newton iteration on the convex
// distance function (converged to 1e-10 m).
//
// Which solid each shape type gives. "Nominal" is the solid the shape's parameters describe
// (include_margin = false); "contact" is the solid Bullet's GJK contacts and convex ray
// tests use (include_margin = true, the default). m = shape.getMargin().
//   btSphereShape     both: ball of getRadius() (the radius is the margin in Bullet).
//   btCapsuleShape    both: segment of 2 getHalfHeight() swept by a ball of getRadius().
//   btBoxShape        both: the box of getHalfExtentsWithMargin() with sharp edges (Bullet's
//                     support function already includes the margin inside the box).
//   btCylinderShape   nominal: sharp cylinder, radius getRadius(), half height from
//                     getHalfExtentsWithMargin(); contact: the core cylinder (radius and half
//                     height minus m) swept by a ball of m, i.e. the same cylinder with its
//                     rims rounded to radius m.
//   btConeShape       nominal: cone of getRadius(), getHeight() (apex at +height/2 along the
//                     up axis); contact: that cone swept by a ball of m (margin OUTSIDE).
//   btConvexHullShape / btConvexPointCloudShape: nominal: convex hull of the scaled points;
//                     contact: that hull swept by a ball of m (margin OUTSIDE).
//   concave meshes (btBvhTriangleMeshShape, btGImpactMeshShape, btHeightfieldTerrainShape,
//                     any btConcaveShape): the triangles (scaling applied by Bullet); with
//                     include_margin and m > 0, every triangle swept by a ball of m (what
//                     Bullet's convex-versus-triangle contacts use; its ray tests ignore it).
//   btCompoundShape   the union of its children at their child transforms.
// Local scaling is applied as Bullet applies it (sphere: x scale only; capsule, cylinder,
// cone: circular cross-section as Bullet's support functions use).
// Any other shape type raises InvalidSetting naming the type.

#include <cstdint>
#include <memory>

#include <BulletCollision/CollisionShapes/btCollisionShape.h>
#include <LinearMath/btTransform.h>

#include "shore/bullet/config.h"
#include "shore/core/envelope.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

/// The column grid: column (i, j) stands at world (origin_x + i * cell, origin_y + j * cell).
struct EnvelopeGrid {
  double origin_x = 0.0;  ///< m, world x of column i = 0; finite
  double origin_y = 0.0;  ///< m, world y of column j = 0; finite
  double cell = 0.01;     ///< m, column spacing; finite, > 0

  void validate() const;
};

struct EnvelopeOptions {
  bool upper = false;                    ///< also compute the highest point (water needs it)
  bool include_margin = true;            ///< contact solid (true) or nominal solid (false), see above
  std::int64_t max_columns = 4'000'000;  ///< windows with more columns are refused; >= 1

  void validate() const;
};

/// Rasterizes shapes on one grid with one set of options. Keeps the triangulated hull of
/// every convex hull shape it has seen (keyed by the shape's address and checked against a
/// hash of its points, so an edited or reallocated shape is triangulated again).
/// Not thread-safe: use one rasterizer per thread.
class EnvelopeRasterizer {
 public:
  /// Throws InvalidSetting if grid or options are invalid.
  EnvelopeRasterizer(const EnvelopeGrid& grid, const EnvelopeOptions& options);
  ~EnvelopeRasterizer();
  EnvelopeRasterizer(EnvelopeRasterizer&&) noexcept;
  EnvelopeRasterizer& operator=(EnvelopeRasterizer&&) noexcept;

  /// The columns that can be covered by `shape` at `pose`: its world AABB snapped outward.
  /// Throws InvalidSetting for a non-finite or non-rotation pose, a non-finite AABB, or a
  /// window of more than options.max_columns columns.
  [[nodiscard]] GridRect window_of(const btCollisionShape& shape, const btTransform& pose) const;

  /// Resets `out` to window_of(shape, pose) and fills it. Returns the number of covered
  /// columns. On error `out` is left with an empty window.
  int rasterize(const btCollisionShape& shape, const btTransform& pose, EnvelopeRaster& out);

  /// Resets `out` to `window` (for callers that clip to an area) and fills it. Returns the
  /// number of covered columns. Throws InvalidSetting as window_of() does, or if `window`
  /// has negative sizes or more than options.max_columns columns.
  int rasterize(const btCollisionShape& shape, const btTransform& pose, const GridRect& window, EnvelopeRaster& out);

  /// Merges the shape into `inout` as it is (min into lower, max into upper if present),
  /// without resetting it: several bodies or parts into one raster. Returns the number of
  /// covered columns of `inout` after the merge. On error `inout` is left unchanged.
  int accumulate(const btCollisionShape& shape, const btTransform& pose, EnvelopeRaster& inout);

  /// Lowest point of `shape` at `pose` on the vertical line through world (x, y), m;
  /// +infinity where the line misses it. For sub-cell detail at a footprint's edges. The
  /// pose must be one rasterize() accepts.
  [[nodiscard]] double lower_at(const btCollisionShape& shape, const btTransform& pose, double x, double y);

  /// Drops all cached hull triangulations.
  void clear_cache() noexcept;

  [[nodiscard]] const EnvelopeGrid& grid() const noexcept { return grid_; }
  [[nodiscard]] const EnvelopeOptions& options() const noexcept { return options_; }

  struct Cache;  ///< opaque: hull triangulations

 private:
  /// Draws the shape into out, all uncovered before; returns how many columns it covers.
  int draw_fresh(const btCollisionShape& shape, const btTransform& pose, EnvelopeRaster& out);

  EnvelopeGrid grid_;
  EnvelopeOptions options_;
  std::unique_ptr<Cache> cache_;
};

/// Largest deviation of a pose's basis from orthonormal that rasterization accepts.
inline constexpr double kMaxBasisDeviation = 1e-3;

/// The shape's reach: the radius of a sphere about its local origin that holds it, margin
/// included (m; not finite for a broken shape).
[[nodiscard]] double shape_reach(const btCollisionShape& shape);

/// Checks, once, that `shape` can be rasterized with `options` on a grid of `cell` metres at
/// any pose: every part is a supported shape type with valid sizes, and no orientation
/// gives it a window of more than options.max_columns columns. Returns shape_reach().
/// Throws InvalidSetting naming the part and the problem.
double check_rasterizable(const btCollisionShape& shape, double cell, const EnvelopeOptions& options);

/// The cheap test before each rasterization of a shape that passed check_rasterizable with
/// this `reach`: true if `pose` is finite, its basis a rotation (kMaxBasisDeviation) and
/// the shape's columns on `grid` within the index range. When it holds, rasterizing the
/// shape at `pose` on `grid` does not throw.
[[nodiscard]] bool pose_rasterizable(const btTransform& pose, double reach, const EnvelopeGrid& grid) noexcept;

/// One-shot form of EnvelopeRasterizer::rasterize (no cache kept between calls).
int rasterize_envelope(const btCollisionShape& shape, const btTransform& pose, const EnvelopeGrid& grid,
                       const EnvelopeOptions& options, EnvelopeRaster& out);

/// One-shot form restricted to `window`.
int rasterize_envelope(const btCollisionShape& shape, const btTransform& pose, const EnvelopeGrid& grid,
                       const EnvelopeOptions& options, const GridRect& window, EnvelopeRaster& out);

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
