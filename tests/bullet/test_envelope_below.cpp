// cylinder_window_below (bullet/src/envelope_below.h, private; a raycast wheel's cut
// envelope) against the whole cylinder's rasterized envelope (itself checked against
// independent geometry in test_envelope.cpp): on random poses, tilted axes included, every
// column reaching at or below the height lies in the cut window, the cut is empty only when
// no column reaches that low, and it does cut.
#include <gtest/gtest.h>

#include <btBulletCollisionCommon.h>

#include <random>

#include "envelope_below.h"
#include "shore/bullet/envelope.h"

using namespace shore::bullet;

TEST(CylinderWindowBelow, HoldsEveryColumnReachingBelowTheHeight) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  EnvelopeOptions opt;
  opt.include_margin = false;
  EnvelopeGrid grid;
  grid.origin_x = -0.013, grid.origin_y = 0.007, grid.cell = 0.01;
  EnvelopeRasterizer rz(grid, opt);
  int cut_somewhere = 0;
  for (int n = 0; n < 200; ++n) {
    const double r = 0.2 + 0.25 * (unit(rng) + 1.0), h = 0.05 + 0.1 * (unit(rng) + 1.0);
    btCylinderShapeX shape{btVector3(btScalar(h), btScalar(r), btScalar(r))};
    shape.setMargin(0);
    // Mostly a wheel's pose (axle near level), every fourth any.
    const double tilt = n % 4 == 0 ? 1.5 : 0.15;
    btQuaternion q(btVector3(0, 0, 1), btScalar(3.2 * unit(rng)));
    q *= btQuaternion(btVector3(0, 1, 0), btScalar(tilt * unit(rng)));
    q *= btQuaternion(btVector3(1, 0, 0), btScalar(3.2 * unit(rng)));
    const btTransform pose(q, btVector3(btScalar(unit(rng)), btScalar(unit(rng)), btScalar(unit(rng))));
    const double cz = double(pose.getOrigin().z()), z_top = cz - r + (r + h) * 1.2 * (unit(rng) + 1.0) / 2.0;
    shore::EnvelopeRaster whole;
    rz.rasterize(shape, pose, whole);
    const btVector3 axle = pose.getBasis().getColumn(0);
    const shore::GridRect cut =
        cylinder_window_below(grid, whole, {double(pose.getOrigin().x()), double(pose.getOrigin().y()), cz},
                              {double(axle.x()), double(axle.y()), double(axle.z())}, h, r, z_top);
    bool any_below = false;
    for (std::int64_t j = whole.j0; j < whole.j1(); ++j)
      for (std::int64_t i = whole.i0; i < whole.i1(); ++i) {
        const double lower = whole.lower[whole.index(i, j)];
        if (!(lower <= z_top)) continue;
        any_below = true;
        EXPECT_TRUE(cut.contains(i, j)) << "pose " << n << " column " << i << ", " << j << ": " << lower
                                        << " <= " << z_top;
      }
    EXPECT_EQ(cut.empty(), !any_below) << "pose " << n;
    if (!cut.empty() && cut.size() < whole.size()) ++cut_somewhere;
  }
  EXPECT_GT(cut_somewhere, 100);  // the bound is not just the whole window
}
