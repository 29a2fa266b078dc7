// Envelope rasterization: settings, input checks, the window, and dispatch by shape type.
#include "shore/bullet/envelope.h"

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCapsuleShape.h>
#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/CollisionShapes/btConeShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btConvexPointCloudShape.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>

#include <unordered_map>

#include "envelope_internal.h"
#include "shore/core/error.h"
#include "shore/core/hash.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

using envelope_detail::Canvas;
using envelope_detail::Frame;
using envelope_detail::HullMesh;
using envelope_detail::Vec3;

struct EnvelopeRasterizer::Cache {
  struct Entry {
    std::uint64_t points_hash = 0;
    HullMesh hull;
  };
  std::unordered_map<const btCollisionShape*, Entry> hulls;
  EnvelopeRaster point;  ///< lower_at's one-column raster
  /// The last pose to_frame accepted and its frame: the same pose again (a probe's many
  /// points on one body) skips the finiteness and orthonormality checks and the conversion,
  /// which cost more than the point.
  btTransform checked_pose;
  Frame checked;
  bool has_checked_pose = false;
};

namespace {

// Compounds nested deeper than this are refused (a cycle or a corrupted shape).
constexpr int kMaxCompoundDepth = 64;
// Grid indices beyond this cannot be represented exactly in double arithmetic.
constexpr double kMaxIndex = 1e15;

void check_finite(const char* field, double v) { Check{"bullet.envelope"}.finite(field, v); }

[[noreturn, gnu::cold, gnu::noinline]] void fail_size(const btCollisionShape& shape, const char* what, double v,
                                                      bool strict) {
  throw InvalidSetting(std::string("shape ") + shape.getName() + " " + what, detail::to_text(v),
                       strict ? "must be finite and > 0" : "must be finite and >= 0");
}

/// Checks a dimension of a shape: finite and >= 0 (> 0 if `strict`). Inline: it runs for
/// every probe point, and the common case builds no message.
inline void check_size(const btCollisionShape& shape, const char* what, double v, bool strict = false) {
  if (!(std::isfinite(v) && v >= 0 && !(strict && v == 0))) fail_size(shape, what, v, strict);
}

double shape_margin(const btCollisionShape& shape, bool include) {
  const double m = static_cast<double>(shape.getMargin());
  check_size(shape, "margin", m);
  return include ? m : 0.0;
}

std::vector<Vec3> scaled_points(const btCollisionShape& shape) {
  std::vector<Vec3> pts;
  if (shape.getShapeType() == CONVEX_HULL_SHAPE_PROXYTYPE) {
    const auto& hull = static_cast<const btConvexHullShape&>(shape);
    pts.reserve(static_cast<std::size_t>(hull.getNumPoints()));
    for (int k = 0; k < hull.getNumPoints(); ++k) pts.push_back(to_vec3(hull.getScaledPoint(k)));
  } else {
    const auto& cloud = static_cast<const btConvexPointCloudShape&>(shape);
    pts.reserve(static_cast<std::size_t>(cloud.getNumPoints()));
    for (int k = 0; k < cloud.getNumPoints(); ++k) pts.push_back(to_vec3(cloud.getScaledPoint(k)));
  }
  for (const Vec3& p : pts) {
    check_size(shape, "point coordinate magnitude", std::abs(p.x) + std::abs(p.y) + std::abs(p.z));
  }
  return pts;
}

/// Bitwise the same rotation and origin (the vectors' unused fourth lanes aside).
bool same_pose(const btTransform& a, const btTransform& b) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (a.getBasis()[r][c] != b.getBasis()[r][c]) return false;
  for (int k = 0; k < 3; ++k)
    if (a.getOrigin()[k] != b.getOrigin()[k]) return false;
  return true;
}

class ShapeDrawer {
 public:
  ShapeDrawer(Canvas& cv, EnvelopeRasterizer::Cache& cache) : cv_(cv), cache_(cache) {}

  void draw(const btCollisionShape& shape, const btTransform& pose, int depth) {
    const Frame f = checked_frame(pose);
    const bool with_margin = cv_.include_margin();
    switch (shape.getShapeType()) {
      case SPHERE_SHAPE_PROXYTYPE: {
        const double r = static_cast<const btSphereShape&>(shape).getRadius();
        check_size(shape, "radius", r);
        envelope_detail::draw_ball(cv_, f.t, r);
        return;
      }
      case BOX_SHAPE_PROXYTYPE: {
        const Vec3 half = to_vec3(static_cast<const btBoxShape&>(shape).getHalfExtentsWithMargin());
        check_size(shape, "half extent x", half.x);
        check_size(shape, "half extent y", half.y);
        check_size(shape, "half extent z", half.z);
        envelope_detail::draw_box(cv_, f, half);
        return;
      }
      case CAPSULE_SHAPE_PROXYTYPE: {
        const auto& capsule = static_cast<const btCapsuleShape&>(shape);
        const double r = capsule.getRadius();
        const double h = capsule.getHalfHeight();
        check_size(shape, "radius", r);
        check_size(shape, "half height", h);
        const Vec3 u = f.axis(capsule.getUpAxis());
        envelope_detail::draw_cylinder(cv_, f.t, u, h, r);
        envelope_detail::draw_ball(cv_, f.t + u * h, r);
        envelope_detail::draw_ball(cv_, f.t - u * h, r);
        return;
      }
      case CYLINDER_SHAPE_PROXYTYPE: {
        const auto& cylinder = static_cast<const btCylinderShape&>(shape);
        const int up = cylinder.getUpAxis();
        const double r = cylinder.getRadius();
        const double h = to_vec3(cylinder.getHalfExtentsWithMargin())[up];
        check_size(shape, "radius", r);
        check_size(shape, "half height", h);
        envelope_detail::draw_rounded_cylinder(cv_, f, up, r, h, shape_margin(shape, with_margin));
        return;
      }
      case CONE_SHAPE_PROXYTYPE: {
        const auto& cone = static_cast<const btConeShape&>(shape);
        const double r = cone.getRadius();
        const double height = cone.getHeight();
        check_size(shape, "radius", r, true);
        check_size(shape, "height", height, true);
        envelope_detail::draw_cone(cv_, f, cone.getConeUpIndex(), r, height, shape_margin(shape, with_margin));
        return;
      }
      case CONVEX_HULL_SHAPE_PROXYTYPE:
      case CONVEX_POINT_CLOUD_SHAPE_PROXYTYPE:
        envelope_detail::draw_hull(cv_, f, hull_of(shape), shape_margin(shape, with_margin));
        return;
      case COMPOUND_SHAPE_PROXYTYPE:
        draw_compound(static_cast<const btCompoundShape&>(shape), pose, depth);
        return;
      default:
        break;
    }
    if (shape.isConcave()) {
      btVector3 mn, mx;
      shape.getAabb(pose, mn, mx);
      envelope_detail::draw_concave(cv_, f, static_cast<const btConcaveShape&>(shape), static_cast<double>(mn.z()),
                                    static_cast<double>(mx.z()), shape_margin(shape, with_margin));
      return;
    }
    throw InvalidSetting("bullet.envelope shape type", shape.getName(),
                         "not supported (sphere, box, capsule, cylinder, cone, convex hull, convex point cloud, "
                         "compound and concave meshes are)");
  }

 private:
  Frame checked_frame(const btTransform& pose) {
    if (cache_.has_checked_pose && same_pose(cache_.checked_pose, pose)) return cache_.checked;
    const Frame f = envelope_detail::to_frame(pose);
    cache_.checked_pose = pose;
    cache_.checked = f;
    cache_.has_checked_pose = true;
    return f;
  }

  void draw_compound(const btCompoundShape& compound, const btTransform& pose, int depth) {
    if (depth >= kMaxCompoundDepth)
      throw InvalidSetting("bullet.envelope compound depth", detail::to_text(depth),
                           "must be < " + detail::to_text(kMaxCompoundDepth));
    for (int k = 0; k < compound.getNumChildShapes(); ++k) {
      const btCollisionShape* child = compound.getChildShape(k);
      if (child) draw(*child, pose * compound.getChildTransform(k), depth + 1);
    }
  }

  const HullMesh& hull_of(const btCollisionShape& shape) {
    const std::vector<Vec3> pts = scaled_points(shape);
    StateHash h;
    h.add(pts.size());
    if (!pts.empty()) h.add_bytes(pts.data(), pts.size() * sizeof(Vec3));
    auto& entry = cache_.hulls[&shape];
    if (entry.points_hash != h.value() || (entry.hull.vertices.empty() && !pts.empty())) {
      entry.hull = envelope_detail::triangulate_hull(pts);
      entry.points_hash = h.value();
    }
    return entry.hull;
  }

  Canvas& cv_;
  EnvelopeRasterizer::Cache& cache_;
};

int count_covered(const EnvelopeRaster& out) {
  int n = 0;
  for (double v : out.lower) n += v < EnvelopeRaster::kNoLower ? 1 : 0;
  return n;
}

void check_window(const GridRect& w, std::int64_t max_columns) {
  const Check c{"bullet.GridRect"};
  c.at_least("nx", w.nx, 0);
  c.at_least("ny", w.ny, 0);
  const double columns = static_cast<double>(w.nx) * static_cast<double>(w.ny);
  if (columns > static_cast<double>(max_columns))
    throw InvalidSetting("bullet.GridRect nx*ny", detail::to_text(columns),
                         "must be <= EnvelopeOptions.max_columns (" + detail::to_text(max_columns) + ")");
  if (std::abs(static_cast<double>(w.i0)) > kMaxIndex || std::abs(static_cast<double>(w.j0)) > kMaxIndex)
    throw InvalidSetting("bullet.GridRect i0/j0", detail::to_text(w.i0) + ", " + detail::to_text(w.j0),
                         "must be within +-1e15");
}

/// The shape's world AABB, checked finite.
void checked_aabb(const btCollisionShape& shape, const btTransform& pose, Vec3& mn, Vec3& mx) {
  btVector3 bmn, bmx;
  shape.getAabb(pose, bmn, bmx);
  mn = to_vec3(bmn);
  mx = to_vec3(bmx);
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(mn[k]) || !std::isfinite(mx[k]))
      throw InvalidSetting(std::string("bullet.envelope AABB of shape ") + shape.getName(),
                           detail::to_text(mn[k]) + " .. " + detail::to_text(mx[k]), "must be finite");
  }
}

}  // namespace

namespace envelope_detail {

Frame frame_of(const btTransform& pose) noexcept {
  Frame f;
  const btMatrix3x3& b = pose.getBasis();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) f.r[r][c] = static_cast<double>(b[r][c]);
  f.t = to_vec3(pose.getOrigin());
  return f;
}

double basis_deviation(const Frame& f) noexcept {
  double worst = 0;
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 3; ++c) {
      const double d = dot(f.axis(a), f.axis(c)) - (a == c ? 1.0 : 0.0);
      worst = std::max(worst, std::abs(d));
    }
  return worst;
}

Frame to_frame(const btTransform& pose) {
  const Frame f = frame_of(pose);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) check_finite("pose.basis", f.r[r][c]);
  check_finite("pose.origin.x", f.t.x);
  check_finite("pose.origin.y", f.t.y);
  check_finite("pose.origin.z", f.t.z);
  const double worst = basis_deviation(f);
  if (!(worst <= kMaxBasisDeviation))
    throw InvalidSetting("bullet.envelope pose.basis", "deviation from orthonormal " + detail::to_text(worst),
                         "must be a rotation (deviation <= 1e-3)");
  return f;
}

}  // namespace envelope_detail

void EnvelopeGrid::validate() const {
  const Check c{"bullet.EnvelopeGrid"};
  c.finite("origin_x", origin_x);
  c.finite("origin_y", origin_y);
  c.positive("cell", cell);
}

void EnvelopeOptions::validate() const {
  Check{"bullet.EnvelopeOptions"}.at_least("max_columns", max_columns, std::int64_t{1});
}

EnvelopeRasterizer::EnvelopeRasterizer(const EnvelopeGrid& grid, const EnvelopeOptions& options)
    : grid_(grid), options_(options), cache_(std::make_unique<Cache>()) {
  grid_.validate();
  options_.validate();
}
EnvelopeRasterizer::~EnvelopeRasterizer() = default;
EnvelopeRasterizer::EnvelopeRasterizer(EnvelopeRasterizer&&) noexcept = default;
EnvelopeRasterizer& EnvelopeRasterizer::operator=(EnvelopeRasterizer&&) noexcept = default;

void EnvelopeRasterizer::clear_cache() noexcept { cache_->hulls.clear(); }

GridRect EnvelopeRasterizer::window_of(const btCollisionShape& shape, const btTransform& pose) const {
  (void)envelope_detail::to_frame(pose);
  Vec3 mn, mx;
  checked_aabb(shape, pose, mn, mx);
  const double fi0 = std::floor((mn.x - grid_.origin_x) / grid_.cell);
  const double fi1 = std::ceil((mx.x - grid_.origin_x) / grid_.cell);
  const double fj0 = std::floor((mn.y - grid_.origin_y) / grid_.cell);
  const double fj1 = std::ceil((mx.y - grid_.origin_y) / grid_.cell);
  for (double v : {fi0, fi1, fj0, fj1}) {
    if (!(std::abs(v) <= kMaxIndex))
      throw InvalidSetting(std::string("bullet.envelope column index of shape ") + shape.getName(), detail::to_text(v),
                           "must be within +-1e15 (shape too far from the grid origin or too large)");
  }
  const double columns = (fi1 - fi0 + 1) * (fj1 - fj0 + 1);
  if (columns > static_cast<double>(options_.max_columns))
    throw InvalidSetting(std::string("bullet.envelope window of shape ") + shape.getName(),
                         detail::to_text(columns) + " columns",
                         "must be <= EnvelopeOptions.max_columns (" + detail::to_text(options_.max_columns) + ")");
  GridRect w;
  w.i0 = static_cast<std::int64_t>(fi0);
  w.j0 = static_cast<std::int64_t>(fj0);
  w.nx = static_cast<int>(fi1 - fi0 + 1);
  w.ny = static_cast<int>(fj1 - fj0 + 1);
  return w;
}

int EnvelopeRasterizer::rasterize(const btCollisionShape& shape, const btTransform& pose, EnvelopeRaster& out) {
  const GridRect w = window_of(shape, pose);
  out.resize(w.i0, w.j0, w.nx, w.ny, options_.upper);
  return draw_fresh(shape, pose, out);
}

int EnvelopeRasterizer::rasterize(const btCollisionShape& shape, const btTransform& pose, const GridRect& window,
                                  EnvelopeRaster& out) {
  check_window(window, options_.max_columns);
  (void)envelope_detail::to_frame(pose);
  Vec3 mn, mx;
  checked_aabb(shape, pose, mn, mx);
  out.resize(window.i0, window.j0, window.nx, window.ny, options_.upper);
  return draw_fresh(shape, pose, out);
}

int EnvelopeRasterizer::draw_fresh(const btCollisionShape& shape, const btTransform& pose, EnvelopeRaster& out) {
  try {
    Canvas cv(out, grid_, options_);
    ShapeDrawer(cv, *cache_).draw(shape, pose, 0);
    return cv.newly_covered();  // the raster was all uncovered: its covered columns
  } catch (...) {
    out.resize(out.i0, out.j0, 0, 0, false);  // never leave a half-drawn raster behind
    throw;
  }
}

double EnvelopeRasterizer::lower_at(const btCollisionShape& shape, const btTransform& pose, double x, double y) {
  EnvelopeRaster& r = cache_->point;
  if (r.i0 == 0 && r.j0 == 0 && r.nx == 1 && r.ny == 1 && r.lower.size() == 1 && r.upper.empty())
    r.lower[0] = EnvelopeRaster::kNoLower;  // what resize would leave, without reallocating
  else
    r.resize(0, 0, 1, 1, false);
  const EnvelopeGrid at{x, y, grid_.cell};  // column (0, 0) of this grid stands at (x, y)
  EnvelopeOptions lower_only = options_;
  lower_only.upper = false;
  Canvas cv(r, at, lower_only);
  ShapeDrawer(cv, *cache_).draw(shape, pose, 0);
  return r.lower[0];
}

int EnvelopeRasterizer::accumulate(const btCollisionShape& shape, const btTransform& pose, EnvelopeRaster& inout) {
  check_window({inout.i0, inout.j0, inout.nx, inout.ny}, options_.max_columns);
  const std::size_t n = static_cast<std::size_t>(inout.nx) * static_cast<std::size_t>(inout.ny);
  if (inout.lower.size() != n || (!inout.upper.empty() && inout.upper.size() != n))
    throw InvalidSetting("bullet.envelope raster sizes", detail::to_text(inout.lower.size()),
                         "lower (and upper if present) must hold nx*ny = " + detail::to_text(n) + " values");
  Vec3 mn, mx;
  checked_aabb(shape, pose, mn, mx);
  // Draw into a scratch copy so that an error half way leaves `inout` untouched.
  EnvelopeRaster scratch = inout;
  Canvas cv(scratch, grid_, options_);
  ShapeDrawer(cv, *cache_).draw(shape, pose, 0);
  inout = std::move(scratch);
  return count_covered(inout);
}

double shape_reach(const btCollisionShape& shape) {
  btVector3 centre;
  btScalar radius = 0;
  shape.getBoundingSphere(centre, radius);
  return static_cast<double>(centre.length()) + static_cast<double>(radius);
}

double check_rasterizable(const btCollisionShape& shape, double cell, const EnvelopeOptions& options) {
  options.validate();
  Check{"bullet.envelope"}.positive("cell", cell);
  const double reach = shape_reach(shape);
  if (!std::isfinite(reach))
    throw InvalidSetting(std::string("bullet.envelope bounding sphere of shape ") + shape.getName(),
                         detail::to_text(reach), "must be finite");
  // Any rotation keeps the shape's AABB inside its bounding sphere: at most this many columns.
  const double span = 2.0 * reach / cell + 3.0;
  if (span * span > static_cast<double>(options.max_columns))
    throw InvalidSetting(std::string("bullet.envelope window of shape ") + shape.getName(),
                         detail::to_text(span * span) + " columns at its widest orientation",
                         "must be <= EnvelopeOptions.max_columns (" + detail::to_text(options.max_columns) + ")");
  // One rasterization at rest checks every part's type and sizes; a grid as coarse as the
  // shape keeps it a few columns.
  EnvelopeRasterizer coarse(EnvelopeGrid{0.0, 0.0, std::max(reach, 1e-3)}, options);
  EnvelopeRaster scratch;
  coarse.rasterize(shape, btTransform::getIdentity(), scratch);
  return reach;
}

bool pose_rasterizable(const btTransform& pose, double reach, const EnvelopeGrid& grid) noexcept {
  const Frame f = envelope_detail::frame_of(pose);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(f.r[r][c])) return false;
  if (!std::isfinite(f.t.x) || !std::isfinite(f.t.y) || !std::isfinite(f.t.z)) return false;
  if (!(envelope_detail::basis_deviation(f) <= kMaxBasisDeviation)) return false;
  // The first and last column index of the window, as window_of() computes them.
  const double di = (std::abs(f.t.x - grid.origin_x) + reach) / grid.cell + 1.0;
  const double dj = (std::abs(f.t.y - grid.origin_y) + reach) / grid.cell + 1.0;
  return di <= kMaxIndex && dj <= kMaxIndex;
}

int rasterize_envelope(const btCollisionShape& shape, const btTransform& pose, const EnvelopeGrid& grid,
                       const EnvelopeOptions& options, EnvelopeRaster& out) {
  EnvelopeRasterizer r(grid, options);
  return r.rasterize(shape, pose, out);
}

int rasterize_envelope(const btCollisionShape& shape, const btTransform& pose, const EnvelopeGrid& grid,
                       const EnvelopeOptions& options, const GridRect& window, EnvelopeRaster& out) {
  EnvelopeRasterizer r(grid, options);
  return r.rasterize(shape, pose, window, out);
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
