#include "shore/render/shape_mesh.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCapsuleShape.h>
#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/CollisionShapes/btConcaveShape.h>
#include <BulletCollision/CollisionShapes/btConeShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btConvexPointCloudShape.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>
#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>
#include <BulletCollision/CollisionShapes/btTriangleCallback.h>
#include <LinearMath/btConvexHullComputer.h>

namespace shore::render {
namespace {

constexpr double kPi = std::numbers::pi;

void add_vertex(ShapeMesh& m, const btVector3& p, const btVector3& n) {
  m.positions.insert(m.positions.end(), {float(p.x()), float(p.y()), float(p.z())});
  m.normals.insert(m.normals.end(), {float(n.x()), float(n.y()), float(n.z())});
}

/// A flat-shaded triangle (its own three vertices, the face normal from its winding),
/// turned to face away from `inside` when one is given.
void add_flat_triangle(ShapeMesh& m, btVector3 a, btVector3 b, btVector3 c, const btVector3* inside = nullptr) {
  btVector3 n = (b - a).cross(c - a);
  if (n.length2() <= btScalar(0)) return;
  n.normalize();
  if (inside != nullptr && n.dot(a - *inside) < 0) {
    std::swap(b, c);
    n = -n;
  }
  const auto base = static_cast<std::uint32_t>(m.vertex_count());
  add_vertex(m, a, n);
  add_vertex(m, b, n);
  add_vertex(m, c, n);
  m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
}

/// A surface of revolution about local axis `up` (0 x, 1 y, 2 z): rings of (radius, height)
/// profile points, smooth normals given per profile point as (radial, axial).
struct ProfilePoint {
  double r, h, nr, nh;
};
void revolve(ShapeMesh& m, const std::vector<ProfilePoint>& profile, int up, int segments, double sx, double sy) {
  const auto base = static_cast<std::uint32_t>(m.vertex_count());
  const int a1 = (up + 1) % 3, a2 = (up + 2) % 3;
  for (const ProfilePoint& p : profile)
    for (int s = 0; s <= segments; ++s) {
      const double phi = 2.0 * kPi * s / segments;
      btVector3 pos, n;
      pos[up] = btScalar(p.h);
      pos[a1] = btScalar(p.r * std::cos(phi) * sx);
      pos[a2] = btScalar(p.r * std::sin(phi) * sy);
      n[up] = btScalar(p.nh);
      n[a1] = btScalar(p.nr * std::cos(phi));
      n[a2] = btScalar(p.nr * std::sin(phi));
      if (n.length2() > 0) n.normalize();
      add_vertex(m, pos, n);
    }
  const auto row = static_cast<std::uint32_t>(segments + 1);
  for (std::uint32_t k = 0; k + 1 < profile.size(); ++k)
    for (std::uint32_t s = 0; s < static_cast<std::uint32_t>(segments); ++s) {
      const std::uint32_t a = base + k * row + s, b = a + 1, c = a + row, d = c + 1;
      // Profile runs from the bottom (-h) up; (a1, a2, up) is right-handed, so a, b, d
      // winds counter-clockwise seen from outside.
      m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
    }
}

ShapeMesh sphere(double r, int segments) {
  std::vector<ProfilePoint> p;
  const int rings = segments / 2;
  for (int k = 0; k <= rings; ++k) {
    const double t = -kPi / 2 + kPi * k / rings;
    p.push_back({r * std::cos(t), r * std::sin(t), std::cos(t), std::sin(t)});
  }
  ShapeMesh m;
  revolve(m, p, 2, segments, 1.0, 1.0);
  return m;
}

ShapeMesh capsule(double r, double half, int up, int segments) {
  std::vector<ProfilePoint> p;
  const int rings = segments / 4;
  for (int k = 0; k <= rings; ++k) {
    const double t = -kPi / 2 + kPi / 2 * k / rings;
    p.push_back({r * std::cos(t), -half + r * std::sin(t), std::cos(t), std::sin(t)});
  }
  for (int k = 0; k <= rings; ++k) {
    const double t = kPi / 2 * k / rings;
    p.push_back({r * std::cos(t), half + r * std::sin(t), std::cos(t), std::sin(t)});
  }
  ShapeMesh m;
  revolve(m, p, up, segments, 1.0, 1.0);
  return m;
}

/// Cylinder (r_bottom == r_top) or cone (r_top == 0) about `up`, with flat caps.
ShapeMesh frustum(double r_bottom, double r_top, double half, int up, int segments) {
  ShapeMesh m;
  const double slope = (r_bottom - r_top) / (2.0 * half);
  const double nl = std::sqrt(1.0 + slope * slope);
  revolve(m, {{0.0, -half, 0.0, -1.0}, {r_bottom, -half, 0.0, -1.0}}, up, segments, 1.0, 1.0);
  revolve(m, {{r_bottom, -half, 1.0 / nl, slope / nl}, {r_top, half, 1.0 / nl, slope / nl}}, up, segments, 1.0, 1.0);
  if (r_top > 0.0) revolve(m, {{r_top, half, 0.0, 1.0}, {0.0, half, 0.0, 1.0}}, up, segments, 1.0, 1.0);
  return m;
}

ShapeMesh box(const btVector3& h) {
  ShapeMesh m;
  for (int axis = 0; axis < 3; ++axis)
    for (int sign = -1; sign <= 1; sign += 2) {
      const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
      btVector3 c[4];
      const double u[4] = {-1, 1, 1, -1}, v[4] = {-1, -1, 1, 1};
      for (int k = 0; k < 4; ++k) {
        c[k][axis] = btScalar(sign) * h[axis];
        c[k][a1] = btScalar(u[k] * sign) * h[a1];
        c[k][a2] = btScalar(v[k]) * h[a2];
      }
      add_flat_triangle(m, c[0], c[1], c[2]);
      add_flat_triangle(m, c[0], c[2], c[3]);
    }
  return m;
}

/// Flat-shaded convex hull of points.
ShapeMesh hull(const std::vector<btVector3>& points) {
  ShapeMesh m;
  if (points.size() < 4) return m;
  btConvexHullComputer ch;
  ch.compute(&points[0].x(), sizeof(btVector3), static_cast<int>(points.size()), 0, 0);
  btVector3 centre(0, 0, 0);
  for (int v = 0; v < ch.vertices.size(); ++v) centre += ch.vertices[v];
  if (ch.vertices.size() > 0) centre /= btScalar(ch.vertices.size());
  for (int f = 0; f < ch.faces.size(); ++f) {
    const btConvexHullComputer::Edge* e0 = &ch.edges[ch.faces[f]];
    const btVector3 a = ch.vertices[e0->getSourceVertex()];
    const btConvexHullComputer::Edge* e = e0->getNextEdgeOfFace();
    btVector3 b = ch.vertices[e->getSourceVertex()];
    for (e = e->getNextEdgeOfFace(); e != e0; e = e->getNextEdgeOfFace()) {
      const btVector3 c = ch.vertices[e->getSourceVertex()];
      add_flat_triangle(m, a, b, c, &centre);
      b = c;
    }
  }
  return m;
}

/// Hull of the support points of a convex shape in directions spread over the sphere.
ShapeMesh sampled_convex(const btConvexShape& shape, int segments) {
  std::vector<btVector3> points;
  const int n = segments * segments;
  for (int k = 0; k < n; ++k) {  // a Fibonacci sphere of directions
    const double z = 1.0 - (2.0 * k + 1.0) / n, r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = k * kPi * (3.0 - std::sqrt(5.0));
    points.push_back(shape.localGetSupportingVertexWithoutMargin(
        btVector3(btScalar(r * std::cos(phi)), btScalar(r * std::sin(phi)), btScalar(z))));
  }
  return hull(points);
}

struct TriangleCollector : btTriangleCallback {
  ShapeMesh* mesh = nullptr;
  void processTriangle(btVector3* t, int, int) override { add_flat_triangle(*mesh, t[0], t[1], t[2]); }
};

void append(ShapeMesh& to, const ShapeMesh& from, const btTransform& t) {
  const auto base = static_cast<std::uint32_t>(to.vertex_count());
  for (std::size_t v = 0; v < from.vertex_count(); ++v) {
    const btVector3 p(from.positions[3 * v], from.positions[3 * v + 1], from.positions[3 * v + 2]);
    const btVector3 n(from.normals[3 * v], from.normals[3 * v + 1], from.normals[3 * v + 2]);
    add_vertex(to, t * p, t.getBasis() * n);
  }
  for (std::uint32_t i : from.indices) to.indices.push_back(base + i);
}

ShapeMesh convex_mesh(const btCollisionShape& shape, int segments) {
  switch (shape.getShapeType()) {
    case SPHERE_SHAPE_PROXYTYPE:
      return sphere(static_cast<const btSphereShape&>(shape).getRadius(), segments);
    case BOX_SHAPE_PROXYTYPE:
      return box(static_cast<const btBoxShape&>(shape).getHalfExtentsWithMargin());
    case CAPSULE_SHAPE_PROXYTYPE: {
      const auto& c = static_cast<const btCapsuleShape&>(shape);
      return capsule(c.getRadius(), c.getHalfHeight(), c.getUpAxis(), segments);
    }
    case CYLINDER_SHAPE_PROXYTYPE: {
      const auto& c = static_cast<const btCylinderShape&>(shape);
      const int up = c.getUpAxis();
      const double half = c.getHalfExtentsWithMargin()[up];
      return frustum(c.getRadius(), c.getRadius(), half, up, segments);
    }
    case CONE_SHAPE_PROXYTYPE: {
      const auto& c = static_cast<const btConeShape&>(shape);
      return frustum(c.getRadius(), 0.0, 0.5 * c.getHeight(), c.getConeUpIndex(), segments);
    }
    case CONVEX_HULL_SHAPE_PROXYTYPE: {
      const auto& h = static_cast<const btConvexHullShape&>(shape);
      std::vector<btVector3> p;
      for (int k = 0; k < h.getNumPoints(); ++k) p.push_back(h.getScaledPoint(k));
      return hull(p);
    }
    case CONVEX_POINT_CLOUD_SHAPE_PROXYTYPE: {
      const auto& h = static_cast<const btConvexPointCloudShape&>(shape);
      std::vector<btVector3> p;
      for (int k = 0; k < h.getNumPoints(); ++k) p.push_back(h.getScaledPoint(k));
      return hull(p);
    }
    default:
      return sampled_convex(static_cast<const btConvexShape&>(shape), segments);
  }
}

}  // namespace

ShapeMesh shape_mesh(const btCollisionShape& shape, int segments) {
  segments = std::max(segments, 8);
  if (shape.isCompound()) {
    const auto& c = static_cast<const btCompoundShape&>(shape);
    ShapeMesh m;
    for (int k = 0; k < c.getNumChildShapes(); ++k)
      append(m, shape_mesh(*c.getChildShape(k), segments), c.getChildTransform(k));
    return m;
  }
  if (shape.getShapeType() == STATIC_PLANE_PROXYTYPE) {
    const auto& p = static_cast<const btStaticPlaneShape&>(shape);
    btVector3 u, v;
    btPlaneSpace1(p.getPlaneNormal(), u, v);
    const btVector3 o = p.getPlaneNormal() * p.getPlaneConstant();
    const btScalar h = 100;
    ShapeMesh m;
    add_flat_triangle(m, o - u * h - v * h, o + u * h - v * h, o + u * h + v * h);
    add_flat_triangle(m, o - u * h - v * h, o + u * h + v * h, o - u * h + v * h);
    return m;
  }
  if (shape.isConcave()) {
    ShapeMesh m;
    TriangleCollector collect;
    collect.mesh = &m;
    const btVector3 big(btScalar(1e30), btScalar(1e30), btScalar(1e30));
    static_cast<const btConcaveShape&>(shape).processAllTriangles(&collect, -big, big);
    return m;
  }
  if (shape.isConvex()) return convex_mesh(shape, segments);
  return {};
}

}  // namespace shore::render
