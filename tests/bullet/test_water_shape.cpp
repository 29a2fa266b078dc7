// The water's view of a shape (bullet/src/water_shape.h, private): convex hulls keep one
// face per plane, and their volume and wet part match the closed forms of the solid.
#include <gtest/gtest.h>

#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>

#include <cmath>
#include <numbers>

#include "water_shape.h"

namespace {

using namespace shore::bullet::water_detail;

/// A regular octagonal prism as a hull of 16 points: circumradius r, height h, centred.
btConvexHullShape octagonal_prism(double r, double h) {
  btConvexHullShape s;
  for (int k = 0; k < 8; ++k) {
    const double a = 2.0 * std::numbers::pi * (k + 0.5) / 8.0;
    for (double z : {-0.5 * h, 0.5 * h})
      s.addPoint(btVector3(btScalar(r * std::cos(a)), btScalar(r * std::sin(a)), btScalar(z)), false);
  }
  s.recalcLocalAabb();
  return s;
}

/// The largest distance of a face's vertices from its plane.
double worst_off_plane(const Polyhedron& p) {
  double worst = 0.0;
  for (std::size_t f = 0; f < p.faces.size(); ++f)
    for (int v : p.faces[f]) {
      const Vec3 x = p.vertices[std::size_t(v)];
      const Vec3 n = p.normals[f];
      worst = std::max(worst, std::abs(n.x * x.x + n.y * x.y + n.z * x.z - p.offsets[f]));
    }
  return worst;
}

TEST(WaterShape, AnOctagonalPrismHullHasOneFacePerPlane) {
  const double r = 0.15, h = 0.2;
  const btConvexHullShape prism = octagonal_prism(r, h);
  const WaterShape s = prepare_shape(prism);
  ASSERT_EQ(s.parts.size(), 1u);
  const Polyhedron& p = s.parts[0].poly;
  EXPECT_EQ(p.faces.size(), 10u);  // 8 sides and 2 octagons, not 28 triangles
  EXPECT_LT(worst_off_plane(p), 1e-7);
  // The octagon's points are floats: the closed form 2 sqrt(2) r^2 h holds to their rounding.
  EXPECT_NEAR(s.volume, 2.0 * std::numbers::sqrt2 * r * r * h, 1e-7 * r * r * h);
}

TEST(WaterShape, AHalfSunkPrismDisplacesHalfItsVolumeAndPresentsWidthTimesDraft) {
  const double r = 0.15, h = 0.2;
  const btConvexHullShape prism = octagonal_prism(r, h);
  const WaterShape s = prepare_shape(prism);
  const WaterPlane w = make_plane(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);  // water at z = 0: half of it under
  Submerged wet;
  add_polyhedron(s.parts[0].poly, shore::bullet::envelope_detail::Frame{}, w, wet);
  EXPECT_NEAR(wet.volume, 0.5 * s.volume, 1e-12 * s.volume);
  EXPECT_NEAR(wet.moment.z / wet.volume, -0.25 * h, 1e-9);  // centre of buoyancy halfway down the wet half
  // Flow along x meets the octagon's width across flats, 2 r cos(pi / 8), over the draft.
  const double width = 2.0 * r * std::cos(std::numbers::pi / 8.0);
  EXPECT_NEAR(projected_area(wet, w, {1.0, 0.0, 0.0}), width * 0.5 * h, 1e-6 * width * h);
  EXPECT_NEAR(projected_area(wet, w, {0.0, 0.0, 1.0}), 2.0 * std::numbers::sqrt2 * r * r, 1e-6 * r * r);
}

TEST(WaterShape, ACylinderIsThirtyTwoSidesAndTwoCaps) {
  const btCylinderShapeZ cylinder(btVector3(0.1f, 0.1f, 0.2f));
  const WaterShape s = prepare_shape(cylinder);
  ASSERT_EQ(s.parts.size(), 1u);
  EXPECT_EQ(s.parts[0].poly.faces.size(), 34u);
  EXPECT_LT(worst_off_plane(s.parts[0].poly), 1e-9);
  EXPECT_NEAR(s.volume, std::numbers::pi * 0.1 * 0.1 * 0.4, 1e-9);
}

}  // namespace
