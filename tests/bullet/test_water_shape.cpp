// The water's view of a shape (bullet/src/water_shape.h, private): convex hulls keep one
// face per plane, and their volume and wet part match the closed forms of the solid.
#include <gtest/gtest.h>

#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

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

/// chord_row one point and one face at a time, as its contract states it: what its vector
/// paths must give bit for bit.
void chord_row_one_by_one(const WorldPlanes& p, double x0, double dx, int n, double y, double* lo, double* hi) {
  for (std::size_t f = 0; f < p.n.size(); ++f) {
    const Vec3 nf = p.n[f];
    const double base = p.d[f] - nf.y * y - nf.x * x0, step = -nf.x * dx;
    for (int k = 0; k < n; ++k) {
      const double rest = base + k * step;
      if (std::abs(nf.z) < 1e-12) {
        if (rest < 0.0) lo[k] = std::numeric_limits<double>::infinity();
      } else if (nf.z > 0.0) {
        const double z = rest * (1.0 / nf.z);
        hi[k] = z < hi[k] ? z : hi[k];
      } else {
        const double z = rest * (1.0 / nf.z);
        lo[k] = z > lo[k] ? z : lo[k];
      }
    }
  }
}

/// Random faces of every kind (looking up, down, upright with n_z exactly 0 and below
/// 1e-12) in a random order, around the origin.
WorldPlanes random_planes(std::mt19937_64& rng, int faces) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  WorldPlanes planes;
  for (int f = 0; f < faces; ++f) {
    Vec3 n{u(rng), u(rng), u(rng)};
    if (f % 7 == 3) n.z = 0.0;
    if (f % 11 == 5) n.z = 1e-13;
    planes.n.push_back(n);
    planes.d.push_back(0.05 + 0.15 * (u(rng) + 1.0));  // the origin inside, points 0.2 m off it often not
  }
  return planes;
}

TEST(WaterShape, ChordRowsGiveTheBitsOfOnePointAtATime) {
  // Random faces over rows of every length up to a few vector blocks, from ends that start
  // at +-inf or at random heights (so min and max pick both ways).
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const WorldPlanes planes = random_planes(rng, 1 + trial % 40);
    const int n = trial % 23;
    const double x0 = u(rng), dx = 0.01 + 0.05 * (u(rng) + 1.0), y = 0.5 * u(rng);
    std::vector<double> lo(std::size_t(n) + 1), hi(std::size_t(n) + 1);
    for (std::size_t k = 0; k < lo.size(); ++k) {
      lo[k] = trial % 2 ? -std::numeric_limits<double>::infinity() : u(rng);
      hi[k] = trial % 2 ? std::numeric_limits<double>::infinity() : u(rng);
    }
    std::vector<double> want_lo = lo, want_hi = hi;
    chord_row_one_by_one(planes, x0, dx, n, y, want_lo.data(), want_hi.data());
    chord_row(planes, x0, dx, n, y, lo.data(), hi.data());
    // Bit for bit, and the point past the row untouched.
    EXPECT_EQ(std::memcmp(lo.data(), want_lo.data(), lo.size() * sizeof(double)), 0) << "trial " << trial;
    EXPECT_EQ(std::memcmp(hi.data(), want_hi.data(), hi.size() * sizeof(double)), 0) << "trial " << trial;
  }
}

TEST(WaterShape, WideningByChordsGivesTheBitsOfChordsThenTheirMerge) {
  // A row's envelope so far (nothing yet, or random ends) widened where the faces' chord
  // is not empty: some points of each row are inside (small offsets: the planes pass near
  // the points), some outside.
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int inside = 0, points = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const WorldPlanes planes = random_planes(rng, 4 + trial % 40);
    const int n = trial % 23;
    const double x0 = 0.1 * u(rng), dx = 0.01, y = 0.1 * u(rng);
    points += n;
    std::vector<double> lower(std::size_t(n) + 1), upper(std::size_t(n) + 1);
    for (std::size_t k = 0; k < lower.size(); ++k) {
      lower[k] = trial % 2 ? std::numeric_limits<double>::infinity() : u(rng);
      upper[k] = trial % 2 ? -std::numeric_limits<double>::infinity() : u(rng);
    }
    std::vector<double> lo(std::size_t(n), -std::numeric_limits<double>::infinity());
    std::vector<double> hi(std::size_t(n), std::numeric_limits<double>::infinity());
    chord_row_one_by_one(planes, x0, dx, n, y, lo.data(), hi.data());
    std::vector<double> want_lower = lower, want_upper = upper;
    for (std::size_t k = 0; k < lo.size(); ++k)
      if (lo[k] < hi[k]) {
        ++inside;
        want_lower[k] = std::min(want_lower[k], lo[k]);
        want_upper[k] = std::max(want_upper[k], hi[k]);
      }
    widen_by_chords(planes, x0, dx, n, y, lower.data(), upper.data());
    EXPECT_EQ(std::memcmp(lower.data(), want_lower.data(), lower.size() * sizeof(double)), 0) << "trial " << trial;
    EXPECT_EQ(std::memcmp(upper.data(), want_upper.data(), upper.size() * sizeof(double)), 0) << "trial " << trial;
  }
  // Both kinds of point were met.
  EXPECT_GT(inside, points / 10);
  EXPECT_LT(inside, points - points / 10);
}

}  // namespace
