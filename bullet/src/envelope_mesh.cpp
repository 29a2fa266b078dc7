// Triangle envelopes: flat triangles, margin-swept triangles, convex hulls and concave meshes.
//
// A column takes the z of a triangle's plane where its vertical line passes through the
// triangle's projection. The inside test uses edge functions evaluated from a canonical
// vertex order, so a column on an edge shared by two triangles is given the same value by
// both: the raster of a closed mesh has no cracks.
#include <BulletCollision/CollisionShapes/btTriangleCallback.h>
#include <LinearMath/btConvexHullComputer.h>

#include <limits>

#include "envelope_internal.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace envelope_detail {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Twice the signed area of (p, q, (x, y)) in the xy plane, evaluated the same way for the
/// edge (p, q) and the edge (q, p) (up to sign).
double edge_function(Vec3 p, Vec3 q, double x, double y) noexcept {
  if (p.x < q.x || (p.x == q.x && p.y < q.y)) return (q.x - p.x) * (y - p.y) - (q.y - p.y) * (x - p.x);
  return -((p.x - q.x) * (y - q.y) - (p.y - q.y) * (x - q.x));
}

/// x range where the horizontal line at y crosses the segment (p, q), merged into [lo, hi].
void merge_row_crossing(Vec3 p, Vec3 q, double y, double& lo, double& hi) noexcept {
  if ((y < p.y && y < q.y) || (y > p.y && y > q.y)) return;
  if (p.y == q.y) {
    lo = std::min({lo, p.x, q.x});
    hi = std::max({hi, p.x, q.x});
    return;
  }
  const double x = p.x + (y - p.y) * (q.x - p.x) / (q.y - p.y);
  lo = std::min(lo, x);
  hi = std::max(hi, x);
}

Vec3 normalized(Vec3 v) noexcept {
  const double n = norm(v);
  return n > 0 ? v * (1.0 / n) : Vec3{};
}

void draw_edge(Canvas& cv, Vec3 p, Vec3 q, double radius) {
  const Vec3 axis = q - p;
  const double length = norm(axis);
  if (length <= 0) return;
  draw_cylinder(cv, (p + q) * 0.5, axis * (1.0 / length), 0.5 * length, radius);
}

class TriangleSink : public btTriangleCallback {
 public:
  TriangleSink(Canvas& cv, const Frame& f, double margin) : cv_(cv), f_(f), margin_(margin) {}
  void processTriangle(btVector3* triangle, int, int) override {
    const Vec3 a = f_.to_world(to_vec3(triangle[0]));
    const Vec3 b = f_.to_world(to_vec3(triangle[1]));
    const Vec3 c = f_.to_world(to_vec3(triangle[2]));
    if (margin_ > 0)
      draw_swept_triangle(cv_, a, b, c, margin_);
    else
      draw_triangle(cv_, a, b, c);
  }

 private:
  Canvas& cv_;
  const Frame& f_;
  double margin_;
};

}  // namespace

void draw_triangle(Canvas& cv, Vec3 a, Vec3 b, Vec3 c) {
  const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  if (area == 0 || !std::isfinite(area)) return;  // seen edge-on: its edges belong to neighbours
  const double sign = area > 0 ? 1.0 : -1.0;
  std::int64_t jlo = 0, jhi = 0, ilo = 0, ihi = 0;
  if (!cv.span_j(std::min({a.y, b.y, c.y}), std::max({a.y, b.y, c.y}), jlo, jhi)) return;
  for (std::int64_t j = jlo; j <= jhi; ++j) {
    const double y = cv.y(j);
    double xlo = kInf;
    double xhi = -kInf;
    merge_row_crossing(a, b, y, xlo, xhi);
    merge_row_crossing(b, c, y, xlo, xhi);
    merge_row_crossing(c, a, y, xlo, xhi);
    if (!cv.span_i(xlo, xhi, ilo, ihi)) continue;
    for (std::int64_t i = ilo; i <= ihi; ++i) {
      const double x = cv.x(i);
      const double eab = sign * edge_function(a, b, x, y);
      const double ebc = sign * edge_function(b, c, x, y);
      const double eca = sign * edge_function(c, a, x, y);
      if (eab < 0 || ebc < 0 || eca < 0) continue;
      const double sum = eab + ebc + eca;
      if (!(sum > 0)) continue;
      const double z = (ebc * a.z + eca * b.z + eab * c.z) / sum;
      cv.put(i, j, z, z);
    }
  }
}

void draw_swept_triangle(Canvas& cv, Vec3 a, Vec3 b, Vec3 c, double m) {
  const Vec3 n = normalized(cross(b - a, c - a)) * m;
  if (dot(n, n) > 0) {
    draw_triangle(cv, a + n, b + n, c + n);
    draw_triangle(cv, a - n, b - n, c - n);
  }
  draw_edge(cv, a, b, m);
  draw_edge(cv, b, c, m);
  draw_edge(cv, c, a, m);
  draw_ball(cv, a, m);
  draw_ball(cv, b, m);
  draw_ball(cv, c, m);
}

HullMesh triangulate_hull(const std::vector<Vec3>& points) {
  HullMesh hull;
  if (points.empty()) return hull;
  std::vector<double> coords;
  coords.reserve(points.size() * 3);
  for (const Vec3& p : points) coords.insert(coords.end(), {p.x, p.y, p.z});
  btConvexHullComputer computer;
  computer.compute(coords.data(), static_cast<int>(3 * sizeof(double)), static_cast<int>(points.size()), btScalar(0),
                   btScalar(0));
  // The computer rounds its output vertices; take the input points they came from instead.
  const int nv = computer.vertices.size();
  hull.vertices.resize(static_cast<std::size_t>(nv));
  for (int v = 0; v < nv; ++v) {
    hull.vertices[static_cast<std::size_t>(v)] = points[static_cast<std::size_t>(computer.original_vertex_index[v])];
    hull.inside = hull.inside + hull.vertices[static_cast<std::size_t>(v)];
  }
  if (nv > 0) hull.inside = hull.inside * (1.0 / nv);
  for (int f = 0; f < computer.faces.size(); ++f) {
    const btConvexHullComputer::Edge* first = &computer.edges[computer.faces[f]];
    const int v0 = first->getSourceVertex();
    const btConvexHullComputer::Edge* e = first->getNextEdgeOfFace();
    int prev = first->getTargetVertex();
    while (e != first && e->getTargetVertex() != v0) {
      const int next = e->getTargetVertex();
      hull.faces.push_back({v0, prev, next});
      prev = next;
      e = e->getNextEdgeOfFace();
    }
  }
  for (int k = 0; k < computer.edges.size(); ++k) {
    const btConvexHullComputer::Edge& e = computer.edges[k];
    if (e.getSourceVertex() < e.getTargetVertex()) hull.edges.push_back({e.getSourceVertex(), e.getTargetVertex()});
  }
  // A single point or collinear points give no edges from the computer: keep the vertices.
  return hull;
}

void draw_hull(Canvas& cv, const Frame& f, const HullMesh& hull, double margin) {
  std::vector<Vec3> world(hull.vertices.size());
  for (std::size_t v = 0; v < world.size(); ++v) world[v] = f.to_world(hull.vertices[v]);
  if (margin <= 0) {
    for (const auto& t : hull.faces) draw_triangle(cv, world[t[0]], world[t[1]], world[t[2]]);
    return;
  }
  // Hull swept by a ball = union of the faces pushed out by the margin, the edges as
  // cylinders and the vertices as balls (every point of the boundary is on one of them).
  const Vec3 inside = f.to_world(hull.inside);
  for (const auto& t : hull.faces) {
    const Vec3 a = world[t[0]], b = world[t[1]], c = world[t[2]];
    const Vec3 n = normalized(cross(b - a, c - a));
    const double side = dot(n, a - inside);
    const double scale = norm(b - a) + norm(c - a);
    if (std::abs(side) <= 1e-12 * scale) {  // flat hull: both sides are outside
      draw_triangle(cv, a + n * margin, b + n * margin, c + n * margin);
      draw_triangle(cv, a - n * margin, b - n * margin, c - n * margin);
    } else {
      const Vec3 out = n * (side > 0 ? margin : -margin);
      draw_triangle(cv, a + out, b + out, c + out);
    }
  }
  for (const auto& e : hull.edges) draw_edge(cv, world[e[0]], world[e[1]], margin);
  for (const Vec3& v : world) draw_ball(cv, v, margin);
}

void draw_concave(Canvas& cv, const Frame& f, const btConcaveShape& shape, double world_z_min, double world_z_max,
                  double margin) {
  if (cv.empty()) return;
  // Local box holding the part of the world that reaches the canvas (plus the margin).
  const double pad = margin + cv.cell();
  const double xs[2] = {cv.x_min() - pad, cv.x_max() + pad};
  const double ys[2] = {cv.y_min() - pad, cv.y_max() + pad};
  const double zs[2] = {world_z_min - pad, world_z_max + pad};
  Vec3 lo{kInf, kInf, kInf};
  Vec3 hi{-kInf, -kInf, -kInf};
  for (double x : xs)
    for (double y : ys)
      for (double z : zs) {
        const Vec3 p = f.to_local_dir(Vec3{x, y, z} - f.t);
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
      }
  TriangleSink sink(cv, f, margin);
  shape.processAllTriangles(&sink, btVector3(btScalar(lo.x), btScalar(lo.y), btScalar(lo.z)),
                            btVector3(btScalar(hi.x), btScalar(hi.y), btScalar(hi.z)));
}

}  // namespace envelope_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
