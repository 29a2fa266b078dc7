#pragma once
// Internal: a body's shape as the water sees it, and its part below a water plane.
//
// A shape is prepared once (add_body) into parts: convex polyhedra (boxes and convex hulls
// exactly; cylinders, cones and capsules as hulls of 32-sided rings scaled radially to the
// solid's exact volume), balls, or "sampled" parts (anything else: its envelopes are
// sampled on a grid). The part of a polyhedron below the plane n . x <= d is integrated
// exactly with the divergence theorem: tetrahedra from a point on the plane to every
// clipped face (the cut face then contributes nothing), which gives the volume, the centre
// of buoyancy and, from the faces' vector areas, the area the part presents to any flow
// direction (half the sum of |A_f . u| over the closed submerged surface). Balls use the
// spherical cap's closed forms.

#include <array>
#include <vector>

#include <BulletCollision/CollisionShapes/btCollisionShape.h>

#include "envelope_internal.h"
#include "shore/bullet/config.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace water_detail {

using envelope_detail::Frame;
using envelope_detail::Vec3;

/// A convex polyhedron in its part's coordinates: faces wound counter-clockwise seen from
/// outside, with outward unit normals and plane offsets (n . x <= offset inside).
struct Polyhedron {
  std::vector<Vec3> vertices;
  std::vector<std::vector<int>> faces;
  std::vector<Vec3> normals;
  std::vector<double> offsets;
};

struct Part {
  enum class Kind { polyhedron, ball, sampled };
  Kind kind = Kind::polyhedron;
  Frame local;                              ///< the part in the body's frame (compound children)
  Polyhedron poly;                          ///< polyhedron
  double radius = 0.0;                      ///< ball
  const btCollisionShape* shape = nullptr;  ///< sampled: the child shape, rasterized
  double volume = 0.0;                      ///< m^3, the part's own (sampled: 0, unknown)
  int axis = -1;                            ///< solids of revolution: their local axis (0, 1, 2)
};

struct WaterShape {
  std::vector<Part> parts;
  double volume = 0.0;   ///< m^3, sum of the parts' known volumes
  bool sampled = false;  ///< some part is sampled
};

/// Prepares a shape (nominal solid: no collision margin added). Throws InvalidSetting
/// naming the field for an unsupported type, a non-finite size or a solid of zero volume.
WaterShape prepare_shape(const btCollisionShape& shape);

/// The water surface under a body: z = z0 + sx (x - x0) + sy (y - y0), as n . X <= d.
struct WaterPlane {
  Vec3 n{0, 0, 1};  ///< unit, up
  double d = 0.0;
  double z0 = 0.0, x0 = 0.0, y0 = 0.0, sx = 0.0, sy = 0.0;
  double vz = 0.0;  ///< m/s, the water's mean vertical velocity there
  [[nodiscard]] double height(double x, double y) const { return z0 + sx * (x - x0) + sy * (y - y0); }
};
WaterPlane make_plane(double x0, double y0, double z0, double sx, double sy, double vz);

/// A submerged face (world): vector area (outward normal times area), centroid, and
/// quadrature points over it (the midpoints of its fan triangles' edges, a third of each
/// triangle's area each: exact for quadratics), for drag that varies over the face.
struct WetFace {
  Vec3 area;
  Vec3 centroid;
  int first_point = 0;  ///< into Submerged::points
  int points = 0;
};
struct FacePoint {
  Vec3 at;
  double weight = 0.0;  ///< m^2
};
/// A submerged ball: centre, radius and depth of the centre below the plane.
struct WetBall {
  Vec3 centre;
  double radius = 0.0;
  double depth = 0.0;
};

/// The parts of a body below the plane (world).
struct Submerged {
  double volume = 0.0;  ///< m^3
  Vec3 moment;          ///< m^4, the integral of x over the submerged volume
  Vec3 cut;             ///< m^2, vector area of the water plane's cut through the polyhedra
  Vec3 cut_points;      ///< sum of the points where the faces' edges cross the plane
  int cut_count = 0;    ///< how many
  std::vector<WetFace> faces;
  std::vector<FacePoint> points;
  std::vector<WetBall> balls;
  void clear() {
    volume = 0.0;
    moment = {};
    cut = {};
    cut_points = {};
    cut_count = 0;
    faces.clear();
    points.clear();
    balls.clear();
  }
};

/// Adds the submerged part of a polyhedron at world frame f.
void add_polyhedron(const Polyhedron& p, const Frame& f, const WaterPlane& w, Submerged& out);
/// Adds the submerged part of a solid of revolution drawn as a ring hull (world frame f,
/// axis the frame's axis `axis`): as add_polyhedron, but the centre of buoyancy is moved
/// into the vertical plane through the axis, as the true solid's lies under a level
/// surface: its pressure forces all cross the axis, the ring hull's facets would otherwise
/// turn it towards a facet.
void add_revolution(const Polyhedron& p, const Frame& f, int axis, const WaterPlane& w, Submerged& out);
/// Adds the submerged cap of a ball (world centre c, radius r).
void add_ball(Vec3 c, double r, const WaterPlane& w, Submerged& out);

/// The area (m^2) the submerged parts present to a flow along the unit direction u.
double projected_area(const Submerged& s, const WaterPlane& w, Vec3 u);

/// The face planes of a polyhedron at world frame f, prepared once per pose for its
/// vertical chords.
struct WorldPlanes {
  std::vector<Vec3> n;
  std::vector<double> d;
  mutable std::vector<double> row_terms;  ///< scratch of chord_row and widen_by_chords
};
void world_planes(const Polyhedron& p, const Frame& f, WorldPlanes& out);
/// The chords of a row of n points (x0 + k dx, y): lo[k] / hi[k] narrowed by every face
/// (start them at -inf / +inf); a point outside gets lo >= hi. Several points to a vector
/// register where the CPU has them, the same bits as one by one (water_chords.cpp).
void chord_row(const WorldPlanes& p, double x0, double dx, int n, double y, double* lo, double* hi);
/// An envelope row widened by the polyhedron's chords: where a point is inside (its chord
/// from -inf / +inf narrowed by chord_row has lo < hi), lower = min(lower, lo) and upper =
/// max(upper, hi); points outside are left alone. The same bits as chord_row and that
/// merge, with no row of chords in memory where AVX is there.
void widen_by_chords(const WorldPlanes& p, double x0, double dx, int n, double y, double* lower, double* upper);

}  // namespace water_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
