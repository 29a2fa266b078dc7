#pragma once
// Internal pieces of envelope rasterization (not installed): double-precision vectors and
// frames, the canvas that primitives draw into, and the primitives themselves.
//
// Every primitive intersects the vertical line through a column with a convex solid and
// merges [entry, exit] into the canvas (min into lower, max into upper). The envelope of a
// union of convex pieces is the min / max over the pieces, which is how compound shapes,
// capsules (cylinder + two balls) and margin-swept hulls (offset faces + edge cylinders +
// vertex balls) are built.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <BulletCollision/CollisionShapes/btConcaveShape.h>
#include <LinearMath/btTransform.h>

#include "bt_convert.h"
#include "shore/bullet/envelope.h"
#include "shore/core/vec3.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace envelope_detail {

using shore::Vec3;

/// A rigid pose in double precision: world = r * local + t.
struct Frame {
  double r[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Vec3 t;

  [[nodiscard]] Vec3 to_world(Vec3 p) const noexcept {
    return {r[0][0] * p.x + r[0][1] * p.y + r[0][2] * p.z + t.x, r[1][0] * p.x + r[1][1] * p.y + r[1][2] * p.z + t.y,
            r[2][0] * p.x + r[2][1] * p.y + r[2][2] * p.z + t.z};
  }
  /// Local coordinates of a world direction (or of a world offset from t).
  [[nodiscard]] Vec3 to_local_dir(Vec3 w) const noexcept {
    return {r[0][0] * w.x + r[1][0] * w.y + r[2][0] * w.z, r[0][1] * w.x + r[1][1] * w.y + r[2][1] * w.z,
            r[0][2] * w.x + r[1][2] * w.y + r[2][2] * w.z};
  }
  /// World direction of local axis k.
  [[nodiscard]] Vec3 axis(int k) const noexcept { return {r[0][k], r[1][k], r[2][k]}; }
};

/// Converts a Bullet pose, unchecked.
Frame frame_of(const btTransform& pose) noexcept;
/// Largest |a_i . a_j - delta_ij| over the basis columns: 0 for a rotation (NaN if not finite).
double basis_deviation(const Frame& f) noexcept;
/// Converts and checks a Bullet pose: finite, and its basis a rotation (kMaxBasisDeviation).
Frame to_frame(const btTransform& pose);

/// Where primitives draw: the output raster, its grid and the options.
class Canvas {
 public:
  Canvas(EnvelopeRaster& out, const EnvelopeGrid& grid, const EnvelopeOptions& options)
      : out_(out), grid_(grid), options_(options), upper_(options.upper && !out.upper.empty()) {}

  /// Columns i whose x lies in [a, b] (padded by a rounding tolerance), clipped to the
  /// raster. False if none.
  bool span_i(double a, double b, std::int64_t& lo, std::int64_t& hi) const noexcept {
    return span(a, b, grid_.origin_x, out_.i0, out_.nx, lo, hi);
  }
  bool span_j(double a, double b, std::int64_t& lo, std::int64_t& hi) const noexcept {
    return span(a, b, grid_.origin_y, out_.j0, out_.ny, lo, hi);
  }
  [[nodiscard]] double x(std::int64_t i) const noexcept { return grid_.origin_x + static_cast<double>(i) * grid_.cell; }
  [[nodiscard]] double y(std::int64_t j) const noexcept { return grid_.origin_y + static_cast<double>(j) * grid_.cell; }
  [[nodiscard]] double cell() const noexcept { return grid_.cell; }
  [[nodiscard]] bool upper() const noexcept { return upper_; }
  [[nodiscard]] bool include_margin() const noexcept { return options_.include_margin; }

  /// Merges the interval [lo, hi] of world heights into column (i, j) (inside the raster).
  void put(std::int64_t i, std::int64_t j, double lo, double hi) noexcept {
    const std::size_t k = out_.index(i, j);
    if (lo < out_.lower[k]) {
      newly_covered_ += out_.lower[k] == EnvelopeRaster::kNoLower ? 1 : 0;
      out_.lower[k] = lo;
    }
    if (upper_ && hi > out_.upper[k]) out_.upper[k] = hi;
  }
  /// How many columns put() covered that were uncovered before (put is the only writer of
  /// the raster): on a fresh raster, every column it covers.
  [[nodiscard]] int newly_covered() const noexcept { return newly_covered_; }

  /// Raster window in world coordinates (x range, y range).
  [[nodiscard]] double x_min() const noexcept { return x(out_.i0); }
  [[nodiscard]] double x_max() const noexcept { return x(out_.i0 + out_.nx - 1); }
  [[nodiscard]] double y_min() const noexcept { return y(out_.j0); }
  [[nodiscard]] double y_max() const noexcept { return y(out_.j0 + out_.ny - 1); }
  [[nodiscard]] bool empty() const noexcept { return out_.nx <= 0 || out_.ny <= 0; }

 private:
  bool span(double a, double b, double origin, std::int64_t first, int count, std::int64_t& lo,
            std::int64_t& hi) const noexcept {
    if (count <= 0 || !(a <= b)) return false;
    const double pad = 1e-9 * (1.0 + std::abs(a) + std::abs(b));
    const double fa = std::ceil((a - pad - origin) / grid_.cell);
    const double fb = std::floor((b + pad - origin) / grid_.cell);
    const double last = static_cast<double>(first + count - 1);
    const double clo = std::max(fa, static_cast<double>(first));
    const double chi = std::min(fb, last);
    if (!(clo <= chi)) return false;
    lo = static_cast<std::int64_t>(clo);
    hi = static_cast<std::int64_t>(chi);
    return true;
  }

  EnvelopeRaster& out_;
  const EnvelopeGrid& grid_;
  const EnvelopeOptions& options_;
  bool upper_;
  int newly_covered_ = 0;
};

// ---- analytic primitives (envelope_convex.cpp) -------------------------------------------

/// Ball of radius r at world centre c.
void draw_ball(Canvas& cv, Vec3 c, double r);
/// Sharp finite cylinder: world centre c, unit axis u, half length h along u, radius r.
void draw_cylinder(Canvas& cv, Vec3 c, Vec3 u, double h, double r);
/// Box of half extents `half` in the frame.
void draw_box(Canvas& cv, const Frame& f, Vec3 half);
/// Cylinder along local axis `up`, radius r, half height h, rims rounded by `margin`
/// (the core of radius r - margin and half height h - margin swept by a ball of margin).
void draw_rounded_cylinder(Canvas& cv, const Frame& f, int up, double r, double h, double margin);
/// Cone along local axis `up` (apex at +height/2), base radius, swept by a ball of margin
/// (margin = 0: the sharp cone).
void draw_cone(Canvas& cv, const Frame& f, int up, double radius, double height, double margin);

// ---- triangles (envelope_mesh.cpp) ---------------------------------------------------------

/// Flat triangle in world coordinates.
void draw_triangle(Canvas& cv, Vec3 a, Vec3 b, Vec3 c);
/// Triangle swept by a ball of radius m: both offset faces, three edge cylinders, three balls.
void draw_swept_triangle(Canvas& cv, Vec3 a, Vec3 b, Vec3 c, double m);

/// A closed convex hull as triangles (outward winding not assumed) and unique edges.
struct HullMesh {
  std::vector<Vec3> vertices;             ///< local coordinates
  std::vector<std::array<int, 3>> faces;  ///< triangles, indices into vertices
  std::vector<std::array<int, 2>> edges;  ///< each hull edge once
  Vec3 inside;                            ///< a point inside (centroid of the vertices)
};
/// Exact hull of the points (vertices are input points, bit for bit).
HullMesh triangulate_hull(const std::vector<Vec3>& points);
/// The hull at frame f, swept by a ball of margin (0: the sharp hull).
void draw_hull(Canvas& cv, const Frame& f, const HullMesh& hull, double margin);
/// Triangles of a concave shape that can reach the canvas window, swept by margin if > 0.
void draw_concave(Canvas& cv, const Frame& f, const btConcaveShape& shape, double world_z_min, double world_z_max,
                  double margin);

}  // namespace envelope_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
