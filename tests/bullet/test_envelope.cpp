// Envelope rasterization against geometry written independently here: every solid is
// described by a function F that is convex along any line and <= 0 exactly inside the
// solid (distance to a core minus a radius, or the max of convex constraints); the
// reference interval on each vertical line is found by ternary search for the minimum of F
// and bisection for its zero crossings. Hulls and meshes are checked against
// Moller-Trumbore ray-triangle intersection over their triangles (hull faces found by
// brute force over point triples).
#include <gtest/gtest.h>

#include <BulletCollision/CollisionShapes/btConvexPointCloudShape.h>
#include <BulletCollision/CollisionShapes/btMultiSphereShape.h>
#include <btBulletCollisionCommon.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "shore/bullet/envelope.h"
#include "shore/core/error.h"

using namespace shore::bullet;
using shore::EnvelopeRaster;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kTolerance = 1e-5;  // m, required agreement of heights
// A column whose line passes within this of the solid's silhouette may be counted either way.
constexpr double kBoundary = 1e-7;

struct Vec {
  double x = 0, y = 0, z = 0;
};
Vec operator+(Vec a, Vec b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec operator-(Vec a, Vec b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec operator*(Vec a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(Vec a, Vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec cross(Vec a, Vec b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double len(Vec a) { return std::sqrt(dot(a, a)); }
Vec vec(const btVector3& v) { return {double(v.x()), double(v.y()), double(v.z())}; }
btVector3 bt(Vec v) { return btVector3(btScalar(v.x), btScalar(v.y), btScalar(v.z)); }

/// A world pose as the test sees it: p_world = o + x * ex + y * ey + z * ez (axes from the
/// btTransform actually used, so float rounding of the pose is shared).
struct Pose {
  btTransform bt;
  Vec o, axis[3];
  Vec world(Vec l) const { return o + axis[0] * l.x + axis[1] * l.y + axis[2] * l.z; }
  Vec local(Vec w) const {
    const Vec d = w - o;
    return {dot(d, axis[0]), dot(d, axis[1]), dot(d, axis[2])};
  }
};

Pose make_pose(std::mt19937& rng, Vec centre_spread) {
  std::normal_distribution<double> n(0, 1);
  std::uniform_real_distribution<double> u(-1, 1);
  double q[4];
  double s = 0;
  for (double& c : q) {
    c = n(rng);
    s += c * c;
  }
  s = std::sqrt(s);
  btQuaternion quat(btScalar(q[0] / s), btScalar(q[1] / s), btScalar(q[2] / s), btScalar(q[3] / s));
  Pose p;
  p.bt.setIdentity();
  p.bt.setRotation(quat);
  // One draw per statement: the order of a call's arguments is unspecified (GCC draws them
  // right to left, clang left to right), and the cases must be the same with every compiler.
  const double dz = u(rng), dy = u(rng), dx = u(rng);
  p.bt.setOrigin(btVector3(btScalar(0.3 + centre_spread.x * dx), btScalar(-0.2 + centre_spread.y * dy),
                           btScalar(1.0 + centre_spread.z * dz)));
  p.o = vec(p.bt.getOrigin());
  for (int k = 0; k < 3; ++k) p.axis[k] = vec(p.bt.getBasis().getColumn(k));
  return p;
}

struct RefInterval {
  bool hit = false;
  double lo = kInf, hi = -kInf;
  double fmin = kInf;
};

/// {z : F(x, y, z) <= 0} for F convex in z.
RefInterval convex_reference(const std::function<double(Vec)>& f, double x, double y, double zlo, double zhi) {
  auto g = [&](double z) { return f({x, y, z}); };
  double a = zlo, b = zhi;
  for (int k = 0; k < 110; ++k) {
    const double m1 = a + (b - a) / 3, m2 = b - (b - a) / 3;
    if (g(m1) < g(m2))
      b = m2;
    else
      a = m1;
  }
  RefInterval r;
  const double zmin = 0.5 * (a + b);
  r.fmin = g(zmin);
  if (r.fmin > 0) return r;
  r.hit = true;
  double l = zlo, h = zmin;
  for (int k = 0; k < 70; ++k) {
    const double m = 0.5 * (l + h);
    (g(m) <= 0 ? h : l) = m;
  }
  r.lo = h;
  l = zmin;
  h = zhi;
  for (int k = 0; k < 70; ++k) {
    const double m = 0.5 * (l + h);
    (g(m) <= 0 ? l : h) = m;
  }
  r.hi = l;
  return r;
}

using Reference = std::function<RefInterval(double x, double y)>;

struct Comparison {
  int covered = 0, reference_covered = 0, boundary_mismatches = 0, failures = 0;
  double worst = 0;
};

/// Rasterizes over the shape's window grown by two columns and compares every column.
Comparison compare(const btCollisionShape& shape, const btTransform& pose, const EnvelopeGrid& grid, bool upper,
                   bool include_margin, const Reference& ref) {
  EnvelopeOptions opt;
  opt.upper = upper;
  opt.include_margin = include_margin;
  EnvelopeRasterizer rz(grid, opt);
  const shore::GridRect w = rz.window_of(shape, pose).grown(2);
  EnvelopeRaster out;
  Comparison c;
  c.covered = rz.rasterize(shape, pose, w, out);
  for (int j = 0; j < w.ny; ++j)
    for (int i = 0; i < w.nx; ++i) {
      const double x = grid.origin_x + double(w.i0 + i) * grid.cell;
      const double y = grid.origin_y + double(w.j0 + j) * grid.cell;
      const RefInterval r = ref(x, y);
      const std::size_t k = out.index(w.i0 + i, w.j0 + j);
      const bool hit = out.covers(k);
      c.reference_covered += r.hit ? 1 : 0;
      if (hit != r.hit) {
        if (std::abs(r.fmin) <= kBoundary)
          ++c.boundary_mismatches;
        else
          ++c.failures;
        continue;
      }
      if (!hit) {
        if (upper && out.upper[k] != EnvelopeRaster::kNoUpper) ++c.failures;
        continue;
      }
      double err = std::abs(out.lower[k] - r.lo);
      if (upper) err = std::max(err, std::abs(out.upper[k] - r.hi));
      c.worst = std::max(c.worst, err);
      if (!(err <= kTolerance)) ++c.failures;
    }
  return c;
}

void expect_good(const Comparison& c, const char* what) {
  EXPECT_EQ(c.failures, 0) << what << ": worst error " << c.worst;
  EXPECT_LE(c.worst, kTolerance) << what;
  EXPECT_GT(c.reference_covered, 20) << what << ": test does not exercise the shape";
  EXPECT_LE(std::abs(c.covered - c.reference_covered), c.boundary_mismatches) << what;
}

EnvelopeGrid grid_of(double cell) {
  EnvelopeGrid g;
  g.origin_x = -0.013;
  g.origin_y = 0.007;
  g.cell = cell;
  return g;
}

// ---- reference solids (world frame) ---------------------------------------------------------

double dist_point_segment(Vec p, Vec a, Vec b) {
  const Vec ab = b - a;
  const double t = std::clamp(dot(p - a, ab) / dot(ab, ab), 0.0, 1.0);
  return len(p - (a + ab * t));
}

/// Cylinder-like solids in the pose's frame with axis `up`: (rho, axial) of a world point.
void meridian(const Pose& pose, int up, Vec p, double& rho, double& a) {
  const Vec l = pose.local(p);
  const double c[3] = {l.x, l.y, l.z};
  a = c[up];
  rho = std::sqrt(c[(up + 1) % 3] * c[(up + 1) % 3] + c[(up + 2) % 3] * c[(up + 2) % 3]);
}

double dist_2d_segment(double px, double py, double ax, double ay, double bx, double by) {
  const double ex = bx - ax, ey = by - ay;
  const double t = std::clamp(((px - ax) * ex + (py - ay) * ey) / (ex * ex + ey * ey), 0.0, 1.0);
  return std::hypot(px - ax - t * ex, py - ay - t * ey);
}

Reference convex_ref(std::function<double(Vec)> f, const Pose& pose, double bound) {
  return [f, bound, c = pose.o](double x, double y) { return convex_reference(f, x, y, c.z - bound, c.z + bound); };
}

// ---- analytic shapes ------------------------------------------------------------------------

TEST(Envelope, SphereMatchesDistanceToCentre) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 6; ++trial) {
    const Pose pose = make_pose(rng, {0.4, 0.4, 0.5});
    const double r = 0.12 + 0.05 * trial;
    btSphereShape shape{btScalar(r)};
    if (trial % 2) shape.setLocalScaling(btVector3(btScalar(1.3), btScalar(0.7), btScalar(2.0)));  // x scale only
    const double rs = r * (trial % 2 ? 1.3 : 1.0);
    auto f = [&](Vec p) { return len(p - pose.o) - rs; };
    expect_good(compare(shape, pose.bt, grid_of(0.013), true, true, convex_ref(f, pose, rs + 1)), "sphere");
  }
}

TEST(Envelope, BoxMatchesSixPlanes) {
  std::mt19937 rng(12);
  for (int trial = 0; trial < 8; ++trial) {
    const Pose pose = make_pose(rng, {0.4, 0.4, 0.5});
    const Vec half{0.1 + 0.03 * trial, 0.25, 0.07};
    btBoxShape shape(bt(half));
    Vec h = half;
    if (trial % 2) {
      shape.setLocalScaling(btVector3(btScalar(0.5), btScalar(1.5), btScalar(2.0)));
      h = {half.x * 0.5, half.y * 1.5, half.z * 2.0};
    }
    auto f = [&](Vec p) {
      const Vec l = pose.local(p);
      return std::max({std::abs(l.x) - h.x, std::abs(l.y) - h.y, std::abs(l.z) - h.z});
    };
    for (bool margin : {true, false})  // a box is the same solid either way
      expect_good(compare(shape, pose.bt, grid_of(0.011), true, margin, convex_ref(f, pose, 2)), "box");
  }
}

TEST(Envelope, CapsuleMatchesDistanceToSegment) {
  std::mt19937 rng(13);
  for (int up = 0; up < 3; ++up)
    for (int trial = 0; trial < 3; ++trial) {
      const Pose pose = make_pose(rng, {0.4, 0.4, 0.5});
      const double r = 0.08 + 0.03 * trial, height = 0.3;
      std::unique_ptr<btCapsuleShape> shape;
      if (up == 0) shape = std::make_unique<btCapsuleShapeX>(btScalar(r), btScalar(height));
      if (up == 1) shape = std::make_unique<btCapsuleShape>(btScalar(r), btScalar(height));
      if (up == 2) shape = std::make_unique<btCapsuleShapeZ>(btScalar(r), btScalar(height));
      double rs = r, hs = 0.5 * height;
      if (trial == 2) {  // Bullet scales the radius by the axis (up + 2) % 3
        const btVector3 scale(btScalar(1.5), btScalar(0.8), btScalar(1.2));
        shape->setLocalScaling(scale);
        rs = r * double(scale[(up + 2) % 3]);
        hs = 0.5 * height * double(scale[up]);
      }
      const Vec a = pose.o + pose.axis[up] * hs, b = pose.o - pose.axis[up] * hs;
      auto f = [&](Vec p) { return dist_point_segment(p, a, b) - rs; };
      expect_good(compare(*shape, pose.bt, grid_of(0.012), true, true, convex_ref(f, pose, 2)), "capsule");
    }
}

TEST(Envelope, CylinderSharpAndRoundedRims) {
  std::mt19937 rng(14);
  for (int up = 0; up < 3; ++up)
    for (int trial = 0; trial < 3; ++trial) {
      const Pose pose = make_pose(rng, {0.4, 0.4, 0.5});
      const double radius = 0.2 + 0.05 * trial, half_height = 0.12;
      btVector3 he(btScalar(0.0), btScalar(0.0), btScalar(0.0));
      for (int k = 0; k < 3; ++k) he[k] = btScalar(k == up ? half_height : radius);
      std::unique_ptr<btCylinderShape> shape;
      if (up == 0) shape = std::make_unique<btCylinderShapeX>(he);
      if (up == 1) shape = std::make_unique<btCylinderShape>(he);
      if (up == 2) shape = std::make_unique<btCylinderShapeZ>(he);
      const double m = trial == 1 ? 0.01 : 0.04;
      shape->setMargin(btScalar(m));
      double r = radius, h = half_height;
      if (trial == 2) {
        btVector3 scale(btScalar(1.25), btScalar(1.25), btScalar(1.25));
        scale[up] = btScalar(1.6);
        shape->setLocalScaling(scale);
        r *= 1.25;
        h *= 1.6;
      }
      auto sharp = [&](Vec p) {
        double rho = 0, a = 0;
        meridian(pose, up, p, rho, a);
        return std::max(rho - r, std::abs(a) - h);
      };
      auto rounded = [&](Vec p) {
        double rho = 0, a = 0;
        meridian(pose, up, p, rho, a);
        return std::hypot(std::max(rho - (r - m), 0.0), std::max(std::abs(a) - (h - m), 0.0)) - m;
      };
      expect_good(compare(*shape, pose.bt, grid_of(0.015), true, false, convex_ref(sharp, pose, 2)), "cylinder sharp");
      expect_good(compare(*shape, pose.bt, grid_of(0.015), true, true, convex_ref(rounded, pose, 2)),
                  "cylinder rounded");
    }
}

// A wheel's pose: its axle level (u.z exactly 0, a column inside the length whole or not
// at all), yawed; and an upright axis (u.x = u.y = 0) and one a hair off it, where the
// line through a column is parallel to the axis. Each against the solid's distance.
TEST(Envelope, CylinderLevelAndUprightAxes) {
  auto posed = [](const btQuaternion& q, const btVector3& at) {
    Pose p;
    p.bt.setIdentity();
    p.bt.setRotation(q);
    p.bt.setOrigin(at);
    p.o = vec(at);
    for (int k = 0; k < 3; ++k) p.axis[k] = vec(p.bt.getBasis().getColumn(k));
    return p;
  };
  const btVector3 at(btScalar(0.31), btScalar(-0.17), btScalar(0.9));
  const double r = 0.4, h = 0.15;
  btCylinderShapeX wheel{btVector3(btScalar(h), btScalar(r), btScalar(r))};
  wheel.setMargin(btScalar(0));
  for (const double yaw : {0.0, 0.3, 1.2}) {
    const Pose pose = posed(btQuaternion(btVector3(0, 0, 1), btScalar(yaw)), at);
    ASSERT_EQ(pose.bt.getBasis().getColumn(0).z(), btScalar(0));  // the level path
    auto sharp = [&](Vec p) {
      double rho = 0, a = 0;
      meridian(pose, 0, p, rho, a);
      return std::max(rho - r, std::abs(a) - h);
    };
    expect_good(compare(wheel, pose.bt, grid_of(0.01), true, true, convex_ref(sharp, pose, 2)), "level wheel");
  }
  btCylinderShapeZ post{btVector3(btScalar(0.2), btScalar(0.2), btScalar(0.3))};
  post.setMargin(btScalar(0));
  for (const double tilt : {0.0, 1e-13}) {
    const Pose pose = posed(btQuaternion(btVector3(1, 0, 0), btScalar(tilt)), at);
    auto sharp = [&](Vec p) {
      double rho = 0, a = 0;
      meridian(pose, 2, p, rho, a);
      return std::max(rho - 0.2, std::abs(a) - 0.3);
    };
    expect_good(compare(post, pose.bt, grid_of(0.013), true, true, convex_ref(sharp, pose, 2)), "upright post");
  }
}

TEST(Envelope, ConeSharpAndSweptByMargin) {
  std::mt19937 rng(15);
  for (int up = 0; up < 3; ++up)
    for (int trial = 0; trial < 3; ++trial) {
      const Pose pose = make_pose(rng, {0.4, 0.4, 0.5});
      double radius = 0.15 + 0.05 * trial, height = 0.35;
      std::unique_ptr<btConeShape> shape;
      if (up == 0) shape = std::make_unique<btConeShapeX>(btScalar(radius), btScalar(height));
      if (up == 1) shape = std::make_unique<btConeShape>(btScalar(radius), btScalar(height));
      if (up == 2) shape = std::make_unique<btConeShapeZ>(btScalar(radius), btScalar(height));
      const double m = trial == 1 ? 0.02 : 0.04;
      shape->setMargin(btScalar(m));
      if (trial == 2) {  // Bullet: height by the up scale, radius by the mean of the other two
        btVector3 scale(btScalar(1.2), btScalar(1.2), btScalar(1.2));
        scale[(up + 1) % 3] = btScalar(1.4);
        scale[up] = btScalar(0.7);
        shape->setLocalScaling(scale);
        radius *= 0.5 * (1.4 + 1.2);
        height *= 0.7;
      }
      const double k = radius / height, half = 0.5 * height;
      auto sharp = [&](Vec p) {
        double rho = 0, a = 0;
        meridian(pose, up, p, rho, a);
        return std::max(rho - k * (half - a), -half - a);
      };
      auto swept = [&](Vec p) {
        double rho = 0, a = 0;
        meridian(pose, up, p, rho, a);
        const bool inside = a >= -half && rho <= k * (half - a);
        if (inside) return -m;
        const double d =
            std::min({dist_2d_segment(rho, a, 0, half, radius, -half), dist_2d_segment(rho, a, radius, -half, 0, -half),
                      dist_2d_segment(rho, a, 0, -half, 0, half)});
        return d - m;
      };
      expect_good(compare(*shape, pose.bt, grid_of(0.012), true, false, convex_ref(sharp, pose, 2)), "cone sharp");
      expect_good(compare(*shape, pose.bt, grid_of(0.012), true, true, convex_ref(swept, pose, 2)), "cone swept");
    }
}

// ---- hulls and meshes ------------------------------------------------------------------------

/// Moller-Trumbore: parameter t of the hit of ray o + t d with triangle (a, b, c), if any.
bool ray_triangle(Vec o, Vec d, Vec a, Vec b, Vec c, double& t) {
  const Vec e1 = b - a, e2 = c - a;
  const Vec p = cross(d, e2);
  const double det = dot(e1, p);
  if (std::abs(det) < 1e-15) return false;
  const double inv = 1.0 / det;
  const Vec s = o - a;
  const double u = dot(s, p) * inv;
  if (u < 0 || u > 1) return false;
  const Vec q = cross(s, e1);
  const double v = dot(d, q) * inv;
  if (v < 0 || u + v > 1) return false;
  t = dot(e2, q) * inv;
  return true;
}

using Triangles = std::vector<std::array<Vec, 3>>;

/// Reference from triangles: lowest and highest hit of the vertical line. `fmin` is the
/// smallest barycentric margin over the triangles, so near-edge columns count as boundary.
RefInterval triangles_reference(const Triangles& tris, double x, double y) {
  RefInterval r;
  r.fmin = kInf;
  const Vec o{x, y, -100}, d{0, 0, 1};
  for (const auto& t : tris) {
    double hit = 0;
    if (ray_triangle(o, d, t[0], t[1], t[2], hit)) {
      r.hit = true;
      r.lo = std::min(r.lo, o.z + hit);
      r.hi = std::max(r.hi, o.z + hit);
    }
    // distance (in xy) of the column to the triangle's outline, for the boundary allowance
    for (int e = 0; e < 3; ++e) {
      const Vec a = t[e], b = t[(e + 1) % 3];
      r.fmin = std::min(r.fmin, dist_2d_segment(x, y, a.x, a.y, b.x, b.y));
    }
  }
  return r;
}

/// Faces of the hull of points in general position, by brute force over triples.
Triangles hull_faces(const std::vector<Vec>& pts) {
  Triangles faces;
  const std::size_t n = pts.size();
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b)
      for (std::size_t c = b + 1; c < n; ++c) {
        const Vec nrm = cross(pts[b] - pts[a], pts[c] - pts[a]);
        int above = 0, below = 0;
        for (std::size_t k = 0; k < n; ++k) {
          if (k == a || k == b || k == c) continue;
          const double s = dot(nrm, pts[k] - pts[a]);
          (s > 0 ? above : below) += 1;
        }
        if (above == 0 || below == 0) faces.push_back({pts[a], pts[b], pts[c]});
      }
  return faces;
}

std::vector<Vec> random_points(std::mt19937& rng, int n, Vec half) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec> pts;
  for (int k = 0; k < n; ++k) {
    // rounded to float so that both builds hold the same points
    pts.push_back({double(float(half.x * u(rng))), double(float(half.y * u(rng))), double(float(half.z * u(rng)))});
  }
  return pts;
}

TEST(Envelope, ConvexHullMatchesRayTriangleOverBruteForceFaces) {
  std::mt19937 rng(16);
  for (int trial = 0; trial < 4; ++trial) {
    const Pose pose = make_pose(rng, {0.4, 0.4, 0.5});
    const std::vector<Vec> pts = random_points(rng, 14, {0.3, 0.2, 0.15});
    btConvexHullShape hull;
    for (const Vec& p : pts) hull.addPoint(bt(p));
    Vec scale{1, 1, 1};
    if (trial % 2) {
      scale = {1.5, 0.5, 1.25};
      hull.setLocalScaling(bt(scale));
    }
    std::vector<Vec> world;
    for (const Vec& p : pts) world.push_back(pose.world({p.x * scale.x, p.y * scale.y, p.z * scale.z}));
    const Triangles faces = hull_faces(world);
    const Comparison c = compare(hull, pose.bt, grid_of(0.011), true, false,
                                 [&](double x, double y) { return triangles_reference(faces, x, y); });
    EXPECT_EQ(c.failures, 0) << "worst " << c.worst;
    EXPECT_GT(c.reference_covered, 100);
    EXPECT_LE(std::abs(c.covered - c.reference_covered), c.boundary_mismatches);
  }
}

double dist_point_triangle(Vec p, Vec a, Vec b, Vec c) {
  const Vec n = cross(b - a, c - a);
  const double nn = dot(n, n);
  // projection inside the triangle: plane distance
  const Vec q = p - n * (dot(p - a, n) / nn);
  const double u = dot(cross(c - b, q - b), n), v = dot(cross(a - c, q - c), n), w = dot(cross(b - a, q - a), n);
  if (u >= 0 && v >= 0 && w >= 0) return std::abs(dot(p - a, n)) / std::sqrt(nn);
  return std::min({dist_point_segment(p, a, b), dist_point_segment(p, b, c), dist_point_segment(p, c, a)});
}

TEST(Envelope, ConvexHullSweptByMarginMatchesDistanceToPolytope) {
  std::mt19937 rng(17);
  for (int trial = 0; trial < 3; ++trial) {
    const Pose pose = make_pose(rng, {0.4, 0.4, 0.5});
    const std::vector<Vec> pts = random_points(rng, 10, {0.25, 0.2, 0.15});
    const double m = trial == 0 ? 0.04 : 0.015;
    btConvexHullShape hull;
    for (const Vec& p : pts) hull.addPoint(bt(p));
    hull.setMargin(btScalar(m));
    std::vector<Vec> world;
    for (const Vec& p : pts) world.push_back(pose.world(p));
    const Triangles faces = hull_faces(world);
    Vec centre;
    for (const Vec& w : world) centre = centre + w * (1.0 / double(world.size()));
    auto f = [&](Vec p) {
      bool inside = true;
      double d = kInf;
      for (const auto& t : faces) {
        Vec n = cross(t[1] - t[0], t[2] - t[0]);
        if (dot(n, centre - t[0]) > 0) n = n * -1.0;
        if (dot(n, p - t[0]) > 0) inside = false;
        d = std::min(d, dist_point_triangle(p, t[0], t[1], t[2]));
      }
      return (inside ? 0.0 : d) - m;
    };
    expect_good(compare(hull, pose.bt, grid_of(0.03), true, true, convex_ref(f, pose, 1.5)), "hull swept");
  }
}

TEST(Envelope, ConvexPointCloudIsItsHull) {
  std::mt19937 rng(18);
  const Pose pose = make_pose(rng, {0.4, 0.4, 0.5});
  const std::vector<Vec> pts = random_points(rng, 12, {0.3, 0.25, 0.2});
  std::vector<btVector3> bpts;
  for (const Vec& p : pts) bpts.push_back(bt(p));
  btConvexPointCloudShape cloud(bpts.data(), int(bpts.size()), btVector3(1, 1, 1));
  std::vector<Vec> world;
  for (const Vec& p : pts) world.push_back(pose.world(p));
  const Triangles faces = hull_faces(world);
  const Comparison c = compare(cloud, pose.bt, grid_of(0.011), true, false,
                               [&](double x, double y) { return triangles_reference(faces, x, y); });
  EXPECT_EQ(c.failures, 0) << "worst " << c.worst;
  EXPECT_GT(c.reference_covered, 100);
}

/// A bumpy open sheet of triangles (a height map with folds), local coordinates.
struct Sheet {
  btTriangleMesh mesh;
  std::vector<std::array<Vec, 3>> local;
};
void build_sheet(Sheet& s, std::mt19937& rng, int n, double size) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec> v;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      v.push_back({double(float(size * (double(i) / n - 0.5) + 0.2 * size / n * u(rng))),
                   double(float(size * (double(j) / n - 0.5) + 0.2 * size / n * u(rng))),
                   double(float(0.1 * size * u(rng)))});
  auto at = [&](int i, int j) { return v[std::size_t(j * (n + 1) + i)]; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::array<Vec, 3> t1{at(i, j), at(i + 1, j), at(i + 1, j + 1)};
      const std::array<Vec, 3> t2{at(i, j), at(i + 1, j + 1), at(i, j + 1)};
      for (const auto& t : {t1, t2}) {
        s.mesh.addTriangle(bt(t[0]), bt(t[1]), bt(t[2]));
        s.local.push_back(t);
      }
    }
}

TEST(Envelope, TriangleMeshMatchesRayTriangle) {
  std::mt19937 rng(19);
  for (int trial = 0; trial < 3; ++trial) {
    Sheet sheet;
    build_sheet(sheet, rng, 6, 0.8);
    btBvhTriangleMeshShape shape(&sheet.mesh, true);
    Vec scale{1, 1, 1};
    if (trial == 2) {
      scale = {1.2, 0.8, 1.5};
      shape.setLocalScaling(bt(scale));
    }
    const Pose pose = make_pose(rng, {0.4, 0.4, 0.5});
    Triangles world;
    for (const auto& t : sheet.local) {
      std::array<Vec, 3> w;
      for (int k = 0; k < 3; ++k) w[k] = pose.world({t[k].x * scale.x, t[k].y * scale.y, t[k].z * scale.z});
      world.push_back(w);
    }
    const Comparison c = compare(shape, pose.bt, grid_of(0.013), true, true,
                                 [&](double x, double y) { return triangles_reference(world, x, y); });
    EXPECT_EQ(c.failures, 0) << "worst " << c.worst;
    EXPECT_GT(c.reference_covered, 500);
    EXPECT_LE(std::abs(c.covered - c.reference_covered), c.boundary_mismatches);
  }
}

TEST(Envelope, CompoundIsTheUnionOfItsChildren) {
  std::mt19937 rng(20);
  btSphereShape sphere(btScalar(0.15));
  btBoxShape box(btVector3(btScalar(0.2), btScalar(0.1), btScalar(0.05)));
  btCompoundShape compound;
  btTransform ts, tb;
  ts.setIdentity();
  ts.setOrigin(btVector3(btScalar(0.2), 0, btScalar(0.05)));
  tb.setIdentity();
  tb.setRotation(btQuaternion(btVector3(0, 1, 1), btScalar(0.6)));
  tb.setOrigin(btVector3(btScalar(-0.1), btScalar(0.05), 0));
  compound.addChildShape(ts, &sphere);
  compound.addChildShape(tb, &box);
  for (int trial = 0; trial < 4; ++trial) {
    const Pose pose = make_pose(rng, {0.4, 0.4, 0.5});
    const btTransform ws = pose.bt * ts, wb = pose.bt * tb;
    const Vec cs = vec(ws.getOrigin()), cb = vec(wb.getOrigin());
    Vec ax[3];
    for (int k = 0; k < 3; ++k) ax[k] = vec(wb.getBasis().getColumn(k));
    auto fs = [&](Vec p) { return len(p - cs) - 0.15; };
    auto fb = [&](Vec p) {
      const Vec d = p - cb;
      return std::max({std::abs(dot(d, ax[0])) - 0.2, std::abs(dot(d, ax[1])) - 0.1, std::abs(dot(d, ax[2])) - 0.05});
    };
    auto ref = [&](double x, double y) {
      const RefInterval a = convex_reference(fs, x, y, pose.o.z - 2, pose.o.z + 2);
      const RefInterval b = convex_reference(fb, x, y, pose.o.z - 2, pose.o.z + 2);
      RefInterval r;
      r.hit = a.hit || b.hit;
      r.lo = std::min(a.lo, b.lo);
      r.hi = std::max(a.hi, b.hi);
      // boundary of the union: near either child's silhouette where the other misses
      r.fmin = std::min(a.hit ? kInf : std::abs(a.fmin), b.hit ? kInf : std::abs(b.fmin));
      if (a.hit && b.hit) r.fmin = kInf;
      return r;
    };
    expect_good(compare(compound, pose.bt, grid_of(0.012), true, true, ref), "compound");
  }
}

TEST(Envelope, LowerOnlyLeavesUpperEmpty) {
  btSphereShape s(btScalar(0.2));
  btTransform pose;
  pose.setIdentity();
  EnvelopeRaster out;
  EnvelopeOptions opt;
  opt.upper = false;
  const int n = rasterize_envelope(s, pose, grid_of(0.02), opt, out);
  EXPECT_TRUE(out.upper.empty());
  // columns within 0.2 of the origin on a 2 cm grid offset by (-0.013, 0.007): count directly
  int expected = 0;
  for (int j = -20; j <= 20; ++j)
    for (int i = -20; i <= 20; ++i) {
      const double x = -0.013 + 0.02 * i, y = 0.007 + 0.02 * j;
      expected += x * x + y * y <= 0.04 ? 1 : 0;
    }
  EXPECT_EQ(n, expected);
}

TEST(Envelope, AccumulateMergesBodies) {
  btSphereShape s(btScalar(0.1));
  btTransform a, b;
  a.setIdentity();
  b.setIdentity();
  a.setOrigin(btVector3(0, 0, 1));
  b.setOrigin(btVector3(btScalar(0.05), 0, btScalar(0.95)));
  EnvelopeOptions opt;
  opt.upper = true;
  EnvelopeRasterizer rz(grid_of(0.01), opt);
  EnvelopeRaster out;
  out.resize(-30, -30, 60, 60, true);
  rz.accumulate(s, a, out);
  rz.accumulate(s, b, out);
  // column nearest (0.027, 0.007): both balls; lower from b, upper from a
  const double x = -0.013 + 0.04, y = 0.007;
  const std::size_t k = out.index(4, 0);
  // the inputs as Bullet holds them (float in the single-precision build)
  const double r2 = std::pow(double(btScalar(0.1)), 2), bx = double(btScalar(0.05)), bz = double(btScalar(0.95));
  const double lb = bz - std::sqrt(r2 - (x - bx) * (x - bx) - y * y);
  const double ua = 1.0 + std::sqrt(r2 - x * x - y * y);
  EXPECT_NEAR(out.lower[k], lb, 1e-9);
  EXPECT_NEAR(out.upper[k], ua, 1e-9);
}

// ---- bad input -------------------------------------------------------------------------------

TEST(Envelope, BadInputRaisesInvalidSetting) {
  btSphereShape s(btScalar(0.2));
  btTransform pose;
  pose.setIdentity();
  EnvelopeRaster out;
  const EnvelopeOptions opt;
  pose.setOrigin(btVector3(std::numeric_limits<btScalar>::quiet_NaN(), 0, 0));
  EXPECT_THROW(rasterize_envelope(s, pose, grid_of(0.01), opt, out), shore::InvalidSetting);
  pose.setIdentity();
  pose.getBasis()[1][1] = std::numeric_limits<btScalar>::infinity();
  EXPECT_THROW(rasterize_envelope(s, pose, grid_of(0.01), opt, out), shore::InvalidSetting);
  pose.setIdentity();
  pose.getBasis()[0][0] = btScalar(2);  // not a rotation
  EXPECT_THROW(rasterize_envelope(s, pose, grid_of(0.01), opt, out), shore::InvalidSetting);
  pose.setIdentity();
  btBoxShape huge(btVector3(btScalar(1e5), btScalar(1e5), btScalar(1)));
  EXPECT_THROW(rasterize_envelope(huge, pose, grid_of(0.01), opt, out), shore::InvalidSetting);
  btSphereShape far(btScalar(1));
  pose.setOrigin(btVector3(btScalar(1e30), 0, 0));
  EXPECT_THROW(rasterize_envelope(far, pose, grid_of(0.01), opt, out), shore::InvalidSetting);
  pose.setIdentity();
  EnvelopeGrid bad = grid_of(0.01);
  bad.cell = 0;
  EXPECT_THROW(rasterize_envelope(s, pose, bad, opt, out), shore::InvalidSetting);
  bad.cell = std::nan("");
  EXPECT_THROW(rasterize_envelope(s, pose, bad, opt, out), shore::InvalidSetting);
  shore::GridRect negative{0, 0, -1, 3};
  EXPECT_THROW(rasterize_envelope(s, pose, grid_of(0.01), opt, negative, out), shore::InvalidSetting);
  btVector3 centres[2] = {btVector3(0, 0, 0), btVector3(1, 0, 0)};
  btScalar radii[2] = {btScalar(0.1), btScalar(0.1)};
  btMultiSphereShape unsupported(centres, radii, 2);
  EXPECT_THROW(rasterize_envelope(unsupported, pose, grid_of(0.01), opt, out), shore::InvalidSetting);
}

// check_rasterizable refuses, once, what rasterizing would refuse at some pose;
// pose_rasterizable is the cheap test for each pose after that.
TEST(Envelope, ShapesAreCheckedOnceAndPosesCheaply) {
  const EnvelopeOptions opt;
  btSphereShape ball(btScalar(0.2));
  const double reach = check_rasterizable(ball, 0.01, opt);
  EXPECT_GE(reach, 0.2);
  EXPECT_LE(reach, 0.2 * std::sqrt(3.0) + 1e-6);  // the bounding sphere of its box
  btBoxShape huge(btVector3(btScalar(1e5), btScalar(1e5), btScalar(1)));
  EXPECT_THROW((void)check_rasterizable(huge, 0.01, opt), shore::InvalidSetting);
  // A box whose window is small lying flat but too large once turned.
  btBoxShape slab(btVector3(btScalar(9.0), btScalar(0.01), btScalar(0.01)));
  EnvelopeOptions tight;
  tight.max_columns = 20000;  // lying along x it covers about 1800 x 5 columns
  EXPECT_THROW((void)check_rasterizable(slab, 0.01, tight), shore::InvalidSetting);
  btVector3 centres[1] = {btVector3(0, 0, 0)};
  btScalar radii[1] = {btScalar(0.1)};
  btMultiSphereShape unsupported(centres, radii, 1);
  btCompoundShape compound;
  compound.addChildShape(btTransform::getIdentity(), &ball);
  compound.addChildShape(btTransform::getIdentity(), &unsupported);
  try {
    (void)check_rasterizable(compound, 0.01, opt);
    ADD_FAILURE() << "an unsupported child shape must be refused";
  } catch (const shore::InvalidSetting& e) {
    EXPECT_NE(std::string(e.what()).find("MultiSphere"), std::string::npos) << e.what();
  }

  btTransform pose = btTransform::getIdentity();
  EXPECT_TRUE(pose_rasterizable(pose, reach, grid_of(0.01)));
  pose.getBasis()[0][0] = btScalar(2);  // not a rotation
  EXPECT_FALSE(pose_rasterizable(pose, reach, grid_of(0.01)));
  pose.setIdentity();
  pose.getBasis()[1][2] = std::numeric_limits<btScalar>::quiet_NaN();
  EXPECT_FALSE(pose_rasterizable(pose, reach, grid_of(0.01)));
  pose.setIdentity();
  pose.setOrigin(btVector3(btScalar(1e30), 0, 0));
  EXPECT_FALSE(pose_rasterizable(pose, reach, grid_of(0.01)));
  pose.setOrigin(btVector3(btScalar(123.4), btScalar(-56.7), btScalar(8.9)));
  ASSERT_TRUE(pose_rasterizable(pose, reach, grid_of(0.01)));
  EnvelopeRaster out;
  EXPECT_NO_THROW(rasterize_envelope(ball, pose, grid_of(0.01), opt, out));
}

TEST(Envelope, FailedAccumulateLeavesRasterUntouched) {
  btSphereShape s(btScalar(0.1));
  btVector3 centres[1] = {btVector3(0, 0, 0)};
  btScalar radii[1] = {btScalar(0.1)};
  btMultiSphereShape unsupported(centres, radii, 1);
  btCompoundShape compound;
  btTransform id;
  id.setIdentity();
  compound.addChildShape(id, &s);
  compound.addChildShape(id, &unsupported);
  EnvelopeRasterizer rz(grid_of(0.01), EnvelopeOptions{});
  EnvelopeRaster out;
  out.resize(-20, -20, 40, 40, false);
  EXPECT_THROW(rz.accumulate(compound, id, out), shore::InvalidSetting);
  for (double v : out.lower) EXPECT_EQ(v, EnvelopeRaster::kNoLower);
}

}  // namespace
