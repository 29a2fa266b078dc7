// The couplings' debugDraw against a recording btIDebugDraw: lines where the contacts and
// the centres of buoyancy are, and nothing when the mode bits are off.
#include <gtest/gtest.h>

#include <vector>

#include <btBulletDynamicsCommon.h>

#include "shore/bullet/debug_draw.h"
#include "shore/bullet/terrain_coupling.h"
#include "shore/bullet/water_coupling.h"
#include "shore/scenes/world.h"

namespace {

namespace dd = shore::bullet::debug_draw;

struct Recorder : btIDebugDraw {
  struct Line {
    btVector3 from, to, colour;
  };
  std::vector<Line> lines;
  int mode = 0;
  void drawLine(const btVector3& a, const btVector3& b, const btVector3& c) override { lines.push_back({a, b, c}); }
  void drawContactPoint(const btVector3&, const btVector3&, btScalar, int, const btVector3&) override {}
  void reportErrorWarning(const char*) override {}
  void draw3dText(const btVector3&, const char*) override {}
  void setDebugMode(int m) override { mode = m; }
  [[nodiscard]] int getDebugMode() const override { return mode; }
  [[nodiscard]] int count(const btVector3& colour) const {
    int n = 0;
    for (const Line& l : lines) n += l.colour == colour ? 1 : 0;
    return n;
  }
};

constexpr double kRadius = 0.1;  // m
constexpr double kX = 0.31, kY = -0.17;

/// A 2 kg ball settled into sand at (kX, kY).
struct SandBall {
  shore::scenes::World world;
  shore::terrain::Terrain soil{[] {
    shore::terrain::TerrainSettings s;
    s.cell = 0.01;
    return s;
  }()};
  shore::bullet::TerrainCoupling coupling{world.world(), soil};
  btRigidBody* ball = world.add_body(std::make_unique<btSphereShape>(btScalar(kRadius)), 2.0,
                                     btVector3(btScalar(kX), btScalar(kY), btScalar(kRadius + 0.01)));
  SandBall() {
    coupling.add_body(ball);
    for (int k = 0; k < 240; ++k) world.step(1.0 / 240.0);
  }
};

TEST(DebugDraw, ContactColumnsLieUnderTheBallAndNothingWithoutModeBits) {
  SandBall s;
  Recorder off;
  s.coupling.debugDraw(&off);
  EXPECT_TRUE(off.lines.empty()) << "mode 0 must draw nothing";
  off.setDebugMode(btIDebugDraw::DBG_DrawWireframe | btIDebugDraw::DBG_DrawConstraints);
  s.coupling.debugDraw(&off);
  EXPECT_TRUE(off.lines.empty()) << "bits the couplings do not use must draw nothing";

  Recorder contacts;
  contacts.setDebugMode(dd::kContactBits);
  s.coupling.debugDraw(&contacts);
  ASSERT_GT(contacts.count(dd::kContactColour), 0);
  EXPECT_EQ(contacts.count(dd::kContactColour), static_cast<int>(contacts.lines.size()));
  const btVector3 c = s.ball->getCenterOfMassPosition();
  for (const Recorder::Line& l : contacts.lines) {
    const btVector3 m = (l.from + l.to) * btScalar(0.5);
    // Contact columns: inside the ball's footprint (radius + a cell), below its centre.
    EXPECT_LE(std::hypot(double(m.x() - c.x()), double(m.y() - c.y())), kRadius + 0.015);
    EXPECT_LT(m.z(), c.z());
  }
}

TEST(DebugDraw, ReactionAndTileOutlinesFollowTheirBits) {
  SandBall s;
  Recorder forces;
  forces.setDebugMode(dd::kForceBits);
  s.coupling.debugDraw(&forces);
  EXPECT_GT(forces.count(dd::kCapacityColour), 0) << "bearing lines at the contact columns";
  EXPECT_EQ(forces.count(dd::kContactColour), 0);
  for (const Recorder::Line& l : forces.lines) {
    if (l.colour == dd::kCapacityColour) {
      EXPECT_GT(l.to.z(), l.from.z()) << "the soil pushes up";
    }
  }
  // The soil's net push on the ball (TerrainCoupling::terrain_force): its arrow's longest line
  // (the shaft) points up.
  double longest = 0.0, rise = 0.0;
  for (const Recorder::Line& l : forces.lines)
    if (l.colour == dd::kForceColour && (l.to - l.from).length() > longest) {
      longest = (l.to - l.from).length();
      rise = l.to.z() - l.from.z();
    }
  EXPECT_GT(longest, 0.0) << "the net reaction arrow";
  EXPECT_GT(rise, 0.0) << "the net reaction pushes up";

  Recorder tiles;
  tiles.setDebugMode(dd::kOutlineBits);
  s.coupling.debugDraw(&tiles);
  ASSERT_GT(tiles.count(dd::kOutlineColour), 0);
  // One outline around the ball: some edge lies on each side of it.
  bool west = false, east = false;
  for (const Recorder::Line& l : tiles.lines) {
    west |= l.from.x() < kX - kRadius && l.to.x() < kX - kRadius;
    east |= l.from.x() > kX + kRadius && l.to.x() > kX + kRadius;
  }
  EXPECT_TRUE(west && east);
}

TEST(DebugDraw, BuoyancyCentreIsUnderTheFloatingBoxAndItsForceHoldsItsWeight) {
  shore::scenes::World world;
  shore::water::PhysicalParameters p;
  p.cell = 0.05;
  shore::water::SurfaceSettings ss = shore::water::SurfaceSettings::physical(p, 41, 41);
  ss.origin_x = ss.origin_y = -1.0;
  shore::water::Surface pond(ss);
  shore::bullet::WaterCoupling coupling(world.world(), pond);
  const double side = 0.3, h = 0.1, ratio = 0.5;
  btRigidBody* box =
      world.add_body(std::make_unique<btBoxShape>(btVector3(btScalar(side / 2), btScalar(side / 2), btScalar(h / 2))),
                     1000.0 * ratio * side * side * h, btVector3(0.1f, 0.05f, 0.0f));
  coupling.add_body(box);
  for (int k = 0; k < 480; ++k) world.step(1.0 / 240.0);

  Recorder off;
  coupling.debugDraw(&off);
  EXPECT_TRUE(off.lines.empty());

  Recorder r;
  r.setDebugMode(dd::kContactBits | dd::kForceBits);
  coupling.debugDraw(&r);
  ASSERT_GE(r.count(dd::kBuoyancyColour), 4);  // a cross (3) and an arrow (1 + head)
  const btVector3 c = box->getCenterOfMassPosition();
  // The first three lines are the cross at the centre of buoyancy: below the centre of mass
  // (half submerged: the centre of the submerged half), over the box.
  const btVector3 centre = (r.lines[0].from + r.lines[0].to) * btScalar(0.5);
  EXPECT_NEAR(centre.x(), c.x(), 0.01);
  EXPECT_NEAR(centre.y(), c.y(), 0.01);
  EXPECT_LT(centre.z(), c.z());
  // The arrow: upward, as long as kArrowPerWeight for a floating body at rest (Archimedes:
  // buoyancy equals the weight), within 10 %.
  const Recorder::Line& shaft = r.lines[3];
  EXPECT_NEAR(shaft.to.z() - shaft.from.z(), dd::kArrowPerWeight, 0.1 * dd::kArrowPerWeight);
}

}  // namespace
