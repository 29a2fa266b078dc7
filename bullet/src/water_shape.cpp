// A body's shape for the water: its parts, and their part below a water plane (see
// water_shape.h).
#include "water_shape.h"

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCapsuleShape.h>
#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/CollisionShapes/btConeShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btConvexPointCloudShape.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "shore/core/det_math.h"
#include "shore/core/error.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace water_detail {

namespace {

constexpr double kPi = det::detail::kPi;
constexpr int kRing = 32;      // sides of the rings that stand for circles
constexpr int kCapRings = 8;   // latitude rings of a capsule's hemisphere
constexpr int kMaxDepth = 64;  // nested compounds

Frame compose(const Frame& a, const Frame& b) {
  Frame c;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) c.r[i][j] = a.r[i][0] * b.r[0][j] + a.r[i][1] * b.r[1][j] + a.r[i][2] * b.r[2][j];
  c.t = a.to_world(b.t);
  return c;
}

void check_positive(const btCollisionShape& shape, const char* what, double v) {
  if (!(v > 0.0) || !std::isfinite(v))
    throw InvalidSetting(std::string("bullet.WaterCoupling.add_body shape ") + shape.getName() + " " + what,
                         detail::to_text(v), "must be finite and > 0 (a floating body needs a volume)");
}

/// Normals and plane offsets from the faces (counter-clockwise seen from outside).
void finish(Polyhedron& p) {
  p.normals.clear();
  p.offsets.clear();
  for (const auto& f : p.faces) {
    Vec3 a{};
    for (std::size_t k = 1; k + 1 < f.size(); ++k)
      a = a + cross(p.vertices[std::size_t(f[k])] - p.vertices[std::size_t(f[0])],
                    p.vertices[std::size_t(f[k + 1])] - p.vertices[std::size_t(f[0])]);
    const double len = norm(a);
    const Vec3 n = len > 0.0 ? a * (1.0 / len) : Vec3{0, 0, 1};
    p.normals.push_back(n);
    p.offsets.push_back(dot(n, p.vertices[std::size_t(f[0])]));
  }
}

double volume_of(const Polyhedron& p) {
  double v = 0.0;
  for (const auto& f : p.faces)
    for (std::size_t k = 1; k + 1 < f.size(); ++k)
      v += dot(p.vertices[std::size_t(f[0])], cross(p.vertices[std::size_t(f[k])], p.vertices[std::size_t(f[k + 1])])) /
           6.0;
  return v;
}

Polyhedron box(Vec3 h) {
  Polyhedron p;
  for (int k = 0; k < 8; ++k) p.vertices.push_back({k & 1 ? h.x : -h.x, k & 2 ? h.y : -h.y, k & 4 ? h.z : -h.z});
  p.faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  finish(p);
  return p;
}

/// The outward triangles of a hull that lie in one plane, merged into one polygon: its
/// boundary (the directed edges whose reverse is not in the group) walked from the first
/// triangle's first boundary edge. Empty if the boundary is not one simple loop.
std::vector<int> merged_face(const std::vector<std::array<int, 3>>& triangles, const std::vector<int>& group) {
  std::vector<std::array<int, 2>> edges;
  for (int t : group)
    for (int k = 0; k < 3; ++k)
      edges.push_back({triangles[std::size_t(t)][std::size_t(k)], triangles[std::size_t(t)][std::size_t((k + 1) % 3)]});
  std::vector<std::array<int, 2>> boundary;
  for (const auto& e : edges)
    if (std::find(edges.begin(), edges.end(), std::array<int, 2>{e[1], e[0]}) == edges.end()) boundary.push_back(e);
  std::vector<int> loop;
  if (boundary.size() < 3) return loop;
  loop.push_back(boundary[0][0]);
  int at = boundary[0][1];
  while (at != loop.front()) {
    if (loop.size() > boundary.size()) return {};
    loop.push_back(at);
    int next = -1, found = 0;
    for (const auto& e : boundary)
      if (e[0] == at) next = e[1], ++found;
    if (found != 1) return {};
    at = next;
  }
  if (loop.size() != boundary.size()) return {};
  return loop;
}

/// The hull of points as a polyhedron of outward faces, one per plane: the hull's triangles
/// that lie in one plane (within 1e-9 of the hull's size) are merged into one convex
/// polygon, so an octagonal prism has 10 faces, not 28 triangles, and a 32-sided cylinder
/// 34, not 124. Clipping it under the water, its drag points and the chord rows of its
/// displacement then visit each face once (the volume and the projected area are the same
/// sums, regrouped).
Polyhedron hull(const std::vector<Vec3>& points) {
  const envelope_detail::HullMesh m = envelope_detail::triangulate_hull(points);
  Polyhedron p;
  p.vertices = m.vertices;
  double size = 0.0;
  for (const Vec3& v : m.vertices) size = std::max(size, norm(v - m.inside));
  const double tolerance = 1e-9 * size;
  std::vector<std::array<int, 3>> triangles;
  std::vector<Vec3> normal;
  for (const auto& t : m.faces) {
    const Vec3 a = m.vertices[std::size_t(t[0])], b = m.vertices[std::size_t(t[1])], c = m.vertices[std::size_t(t[2])];
    const Vec3 n = cross(b - a, c - a);
    const bool outward = dot(n, a - m.inside) >= 0.0;
    triangles.push_back(outward ? t : std::array<int, 3>{t[0], t[2], t[1]});
    const double len = norm(n);
    normal.push_back(len > 0.0 ? n * ((outward ? 1.0 : -1.0) / len) : Vec3{});
  }
  // Groups in the order of their first triangle; a triangle joins the first group whose
  // plane holds its three vertices and faces its way.
  std::vector<std::vector<int>> groups;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    bool joined = false;
    for (auto& g : groups) {
      const std::size_t first = std::size_t(g.front());
      const Vec3 n = normal[first];
      const double d = dot(n, m.vertices[std::size_t(triangles[first][0])]);
      bool in_plane = dot(n, normal[t]) > 0.5;
      for (int v : triangles[t]) in_plane = in_plane && std::abs(dot(n, m.vertices[std::size_t(v)]) - d) <= tolerance;
      if (in_plane) {
        g.push_back(static_cast<int>(t));
        joined = true;
        break;
      }
    }
    if (!joined) groups.push_back({static_cast<int>(t)});
  }
  for (const auto& g : groups) {
    std::vector<int> face = g.size() > 1 ? merged_face(triangles, g) : std::vector<int>{};
    if (!face.empty()) {
      p.faces.push_back(std::move(face));
      continue;
    }
    for (int t : g) {  // a single triangle, or a group whose boundary is not one loop
      const auto& tri = triangles[std::size_t(t)];
      p.faces.push_back({tri[0], tri[1], tri[2]});
    }
  }
  finish(p);
  return p;
}

/// Local coordinates with axis `up` as the third.
Vec3 on_axis(int up, double radial_a, double radial_b, double along) {
  switch (up) {
    case 0:
      return {along, radial_a, radial_b};
    case 1:
      return {radial_b, along, radial_a};
    default:
      return {radial_a, radial_b, along};
  }
}

/// A solid of revolution about axis `up`: rings (along, radius) of kRing points, made a
/// hull and scaled radially to the solid's exact volume.
Polyhedron revolution(int up, const std::vector<std::pair<double, double>>& rings, double exact_volume) {
  const auto points = [&](double scale) {
    std::vector<Vec3> pts;
    for (const auto& [along, radius] : rings) {
      if (radius <= 0.0) {
        pts.push_back(on_axis(up, 0.0, 0.0, along));
        continue;
      }
      for (int k = 0; k < kRing; ++k) {
        const double a = 2.0 * kPi * k / kRing;
        pts.push_back(on_axis(up, scale * radius * det::cos(a), scale * radius * det::sin(a), along));
      }
    }
    return pts;
  };
  const Polyhedron first = hull(points(1.0));
  const double v = volume_of(first);
  return v > 0.0 ? hull(points(std::sqrt(exact_volume / v))) : first;
}

void add_part(WaterShape& out, Part part) {
  out.volume += part.volume;
  out.sampled = out.sampled || part.kind == Part::Kind::sampled;
  out.parts.push_back(std::move(part));
}

void prepare(const btCollisionShape& shape, const Frame& local, int depth, WaterShape& out) {
  Part part;
  part.local = local;
  switch (shape.getShapeType()) {
    case SPHERE_SHAPE_PROXYTYPE: {
      part.kind = Part::Kind::ball;
      part.radius = static_cast<const btSphereShape&>(shape).getRadius();
      check_positive(shape, "radius", part.radius);
      part.volume = 4.0 / 3.0 * kPi * part.radius * part.radius * part.radius;
      add_part(out, std::move(part));
      return;
    }
    case BOX_SHAPE_PROXYTYPE: {
      const Vec3 h = to_vec3(static_cast<const btBoxShape&>(shape).getHalfExtentsWithMargin());
      check_positive(shape, "half extent x", h.x);
      check_positive(shape, "half extent y", h.y);
      check_positive(shape, "half extent z", h.z);
      part.poly = box(h);
      part.volume = 8.0 * h.x * h.y * h.z;
      add_part(out, std::move(part));
      return;
    }
    case CONVEX_HULL_SHAPE_PROXYTYPE:
    case CONVEX_POINT_CLOUD_SHAPE_PROXYTYPE: {
      std::vector<Vec3> pts;
      if (shape.getShapeType() == CONVEX_HULL_SHAPE_PROXYTYPE) {
        const auto& h = static_cast<const btConvexHullShape&>(shape);
        for (int k = 0; k < h.getNumPoints(); ++k) pts.push_back(to_vec3(h.getScaledPoint(k)));
      } else {
        const auto& h = static_cast<const btConvexPointCloudShape&>(shape);
        for (int k = 0; k < h.getNumPoints(); ++k) pts.push_back(to_vec3(h.getScaledPoint(k)));
      }
      for (const Vec3& p : pts)
        check_positive(shape, "point coordinate magnitude", 1.0 + std::abs(p.x) + std::abs(p.y) + std::abs(p.z));
      part.poly = hull(pts);
      part.volume = volume_of(part.poly);
      check_positive(shape, "hull volume", part.volume);
      add_part(out, std::move(part));
      return;
    }
    case CYLINDER_SHAPE_PROXYTYPE: {
      const auto& c = static_cast<const btCylinderShape&>(shape);
      const int up = c.getUpAxis();
      const double r = c.getRadius(), h = to_vec3(c.getHalfExtentsWithMargin())[up];
      check_positive(shape, "radius", r);
      check_positive(shape, "half height", h);
      part.volume = 2.0 * kPi * r * r * h;
      part.poly = revolution(up, {{-h, r}, {h, r}}, part.volume);
      part.axis = up;
      add_part(out, std::move(part));
      return;
    }
    case CONE_SHAPE_PROXYTYPE: {
      const auto& c = static_cast<const btConeShape&>(shape);
      const double r = c.getRadius(), height = c.getHeight();
      check_positive(shape, "radius", r);
      check_positive(shape, "height", height);
      part.volume = kPi * r * r * height / 3.0;
      part.poly = revolution(c.getConeUpIndex(), {{-0.5 * height, r}, {0.5 * height, 0.0}}, part.volume);
      part.axis = c.getConeUpIndex();
      add_part(out, std::move(part));
      return;
    }
    case CAPSULE_SHAPE_PROXYTYPE: {
      const auto& c = static_cast<const btCapsuleShape&>(shape);
      const double r = c.getRadius(), h = c.getHalfHeight();
      check_positive(shape, "radius", r);
      if (!(h >= 0.0) || !std::isfinite(h))
        throw InvalidSetting(std::string("bullet.WaterCoupling.add_body shape ") + shape.getName() + " half height",
                             detail::to_text(h), "must be finite and >= 0");
      std::vector<std::pair<double, double>> rings;
      for (int k = kCapRings; k >= 0; --k) {
        const double a = 0.5 * kPi * k / kCapRings;  // from the pole (k = kCapRings) to the equator (k = 0)
        rings.emplace_back(-h - r * det::sin(a), r * det::cos(a));
      }
      for (int k = 0; k <= kCapRings; ++k) {
        const double a = 0.5 * kPi * k / kCapRings;
        rings.emplace_back(h + r * det::sin(a), r * det::cos(a));
      }
      part.volume = 2.0 * kPi * r * r * h + 4.0 / 3.0 * kPi * r * r * r;
      part.poly = revolution(c.getUpAxis(), rings, part.volume);
      part.axis = c.getUpAxis();
      add_part(out, std::move(part));
      return;
    }
    case COMPOUND_SHAPE_PROXYTYPE: {
      if (depth >= kMaxDepth)
        throw InvalidSetting("bullet.WaterCoupling.add_body compound depth", detail::to_text(depth),
                             "must be < " + detail::to_text(kMaxDepth));
      const auto& c = static_cast<const btCompoundShape&>(shape);
      for (int k = 0; k < c.getNumChildShapes(); ++k)
        if (const btCollisionShape* child = c.getChildShape(k))
          prepare(*child, compose(local, envelope_detail::frame_of(c.getChildTransform(k))), depth + 1, out);
      return;
    }
    default:
      break;
  }
  if (shape.isConcave()) {  // triangle meshes: their envelopes are sampled
    part.kind = Part::Kind::sampled;
    part.shape = &shape;
    add_part(out, std::move(part));
    return;
  }
  throw InvalidSetting("bullet.WaterCoupling.add_body shape type", shape.getName(),
                       "not supported (sphere, box, capsule, cylinder, cone, convex hull, convex point cloud, "
                       "compound and concave meshes are)");
}

}  // namespace

WaterShape prepare_shape(const btCollisionShape& shape) {
  WaterShape s;
  prepare(shape, Frame{}, 0, s);
  if (!s.sampled && !(s.volume > 0.0))
    throw InvalidSetting(std::string("bullet.WaterCoupling.add_body shape ") + shape.getName() + " volume",
                         detail::to_text(s.volume), "must be > 0 (a floating body needs a volume)");
  return s;
}

WaterPlane make_plane(double x0, double y0, double z0, double sx, double sy, double vz) {
  WaterPlane w;
  w.x0 = x0;
  w.y0 = y0;
  w.z0 = z0;
  w.sx = sx;
  w.sy = sy;
  w.vz = vz;
  const Vec3 n{-sx, -sy, 1.0};
  w.n = n * (1.0 / norm(n));
  w.d = dot(w.n, Vec3{x0, y0, z0});
  return w;
}

void add_polyhedron(const Polyhedron& p, const Frame& f, const WaterPlane& w, Submerged& out) {
  std::vector<Vec3> world(p.vertices.size());
  std::vector<double> depth(p.vertices.size());  // signed distance above the plane (<= 0: wet)
  bool any_wet = false;
  for (std::size_t k = 0; k < world.size(); ++k) {
    world[k] = f.to_world(p.vertices[k]);
    depth[k] = dot(w.n, world[k]) - w.d;
    any_wet = any_wet || depth[k] < 0.0;
  }
  if (!any_wet) return;
  const Vec3 p0 = w.n * w.d;  // on the plane: the cut face adds no tetrahedra
  std::vector<Vec3> q;
  for (const auto& face : p.faces) {
    q.clear();
    for (std::size_t k = 0; k < face.size(); ++k) {  // Sutherland-Hodgman against n . x <= d
      const std::size_t a = std::size_t(face[k]), b = std::size_t(face[(k + 1) % face.size()]);
      if (depth[a] <= 0.0) q.push_back(world[a]);
      if ((depth[a] < 0.0) != (depth[b] < 0.0) && depth[a] != depth[b]) {
        q.push_back(world[a] + (world[b] - world[a]) * (depth[a] / (depth[a] - depth[b])));
        out.cut_points = out.cut_points + q.back();
        ++out.cut_count;
      }
    }
    if (q.size() < 3) continue;
    Vec3 area{}, weighted{};
    double twice = 0.0;
    const int first = static_cast<int>(out.points.size());
    for (std::size_t k = 1; k + 1 < q.size(); ++k) {
      const double vol = dot(q[0] - p0, cross(q[k] - p0, q[k + 1] - p0)) / 6.0;
      out.volume += vol;
      out.moment = out.moment + (p0 + q[0] + q[k] + q[k + 1]) * (0.25 * vol);
      const Vec3 a = cross(q[k] - q[0], q[k + 1] - q[0]);
      area = area + a;
      const double s = norm(a);
      twice += s;
      weighted = weighted + (q[0] + q[k] + q[k + 1]) * (s / 3.0);
      const double third = s / 6.0;  // a third of the triangle's area
      out.points.push_back({(q[0] + q[k]) * 0.5, third});
      out.points.push_back({(q[k] + q[k + 1]) * 0.5, third});
      out.points.push_back({(q[k + 1] + q[0]) * 0.5, third});
    }
    area = area * 0.5;
    if (twice > 0.0)
      out.faces.push_back({area, weighted * (1.0 / twice), first, static_cast<int>(out.points.size()) - first});
    out.cut = out.cut - area;  // a closed surface's vector areas sum to zero
  }
}

void add_revolution(const Polyhedron& p, const Frame& f, int axis, const WaterPlane& w, Submerged& out) {
  const double v0 = out.volume;
  const Vec3 m0 = out.moment;
  add_polyhedron(p, f, w, out);
  const double v = out.volume - v0;
  if (!(v > 0.0)) return;
  const Vec3 c = (out.moment - m0) * (1.0 / v);
  const Vec3 a = f.axis(axis), side = cross(Vec3{0, 0, 1}, a);
  const double len = norm(side);
  if (len < 1e-9) return;  // a vertical axis: buoyancy has no moment about it anyway
  const Vec3 e = side * (1.0 / len);
  out.moment = out.moment - e * (dot(e, c - f.t) * v);
}

void add_ball(Vec3 c, double r, const WaterPlane& w, Submerged& out) {
  const double depth = w.d - dot(w.n, c);
  const double h = std::clamp(r + depth, 0.0, 2.0 * r);  // height of the wet cap
  if (h <= 0.0) return;
  const double v = kPi * h * h * (3.0 * r - h) / 3.0;
  const double below = 3.0 * (2.0 * r - h) * (2.0 * r - h) / (4.0 * (3.0 * r - h));  // centroid below the centre
  out.volume += v;
  out.moment = out.moment + (c - w.n * below) * v;
  out.balls.push_back({c, r, depth});
}

namespace {
double acos_det(double x) {
  x = std::clamp(x, -1.0, 1.0);
  return det::atan2(std::sqrt(1.0 - x * x), x);
}
double asin_det(double x) {
  x = std::clamp(x, -1.0, 1.0);
  return det::atan2(x, std::sqrt(1.0 - x * x));
}
/// Area of the part s <= x of a disc of radius r centred at 0.
double segment(double r, double x) {
  x = std::clamp(x, -r, r);
  return r * r * (kPi - acos_det(x / r)) + x * std::sqrt(std::max(0.0, r * r - x * x));
}
/// Integral over [lo, hi] of 2 sqrt(rho^2 - s^2).
double strip(double rho, double lo, double hi) {
  const auto f = [rho](double s) {
    s = std::clamp(s, -rho, rho);
    return s * std::sqrt(std::max(0.0, rho * rho - s * s)) + rho * rho * asin_det(s / rho);
  };
  return hi > lo ? f(hi) - f(lo) : 0.0;
}

/// The projection along u of the part of a ball below the plane: its disc where the line
/// along u through a point meets the wet cap, in closed form (a circular segment, and the
/// projected cut ellipse's share).
double ball_projected(const WetBall& b, const WaterPlane& w, Vec3 u) {
  const double r = b.radius, depth = b.depth;
  if (depth >= r) return kPi * r * r;
  if (depth <= -r) return 0.0;
  const double c = std::min(1.0, std::abs(dot(w.n, u))), s = std::sqrt(std::max(0.0, 1.0 - c * c));
  if (s < 1e-12) return depth >= 0.0 ? kPi * r * r : kPi * (r * r - depth * depth);
  if (c < 1e-12) return segment(r, depth);
  // Points at distance t along the plane's normal's projection e: wet iff t s - c L <= depth,
  // L the half chord; t <= depth / s is wet whole, beyond it the cut ellipse's strip.
  const double t0 = depth / s;
  const double whole = t0 >= -r ? segment(r, std::min(r, t0)) : 0.0;
  const double rho = c * std::sqrt(r * r - depth * depth), mid = depth * s;
  const double lo = std::max({-r, t0, mid - rho}), hi = std::min(r, mid + rho);
  return whole + strip(rho, lo - mid, hi - mid) / c;
}
}  // namespace

double projected_area(const Submerged& s, const WaterPlane& w, Vec3 u) {
  double a = std::abs(dot(s.cut, u));
  for (const WetFace& f : s.faces) a += std::abs(dot(f.area, u));
  a *= 0.5;
  for (const WetBall& b : s.balls) a += ball_projected(b, w, u);
  return a;
}

void world_planes(const Polyhedron& p, const Frame& f, WorldPlanes& out) {
  out.n.resize(p.normals.size());
  out.d.resize(p.normals.size());
  for (std::size_t k = 0; k < p.normals.size(); ++k) {
    const Vec3 n = f.to_world(p.normals[k]) - f.t;
    out.n[k] = n;
    out.d[k] = p.offsets[k] + dot(n, f.t);
  }
}

}  // namespace water_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
