// A ball resting on a HeightfieldTile must rest where geometry says: on the tile's world
// heights, at the tile's world position (checks the placement rules of Bullet 3.24).
#include <gtest/gtest.h>

#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <memory>

#include "shore/bullet/heightfield_tile.h"
#include "shore/core/error.h"

using namespace shore::bullet;

namespace {
double rest_height_of_ball_on(HeightfieldTile& tile, double x, double y, double radius) {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
  world.setGravity(btVector3(0, 0, btScalar(-9.81)));
  world.addCollisionObject(tile.object());
  btSphereShape sphere{btScalar(radius)};
  btVector3 inertia;
  sphere.calculateLocalInertia(btScalar(1), inertia);
  btTransform start;
  start.setIdentity();
  start.setOrigin(btVector3(btScalar(x), btScalar(y), btScalar(tile.height(0, 0) + 0.3)));
  btDefaultMotionState motion(start);
  btRigidBody ball(btRigidBody::btRigidBodyConstructionInfo(btScalar(1), &motion, &sphere, inertia));
  ball.setRollingFriction(btScalar(0.1));
  world.addRigidBody(&ball);
  for (int k = 0; k < 480; ++k) world.stepSimulation(btScalar(1.0 / 240), 1, btScalar(1.0 / 240));
  const double z = ball.getWorldTransform().getOrigin().z();
  world.removeRigidBody(&ball);
  world.removeCollisionObject(tile.object());
  return z;
}
}  // namespace

TEST(HeightfieldTile, BallRestsOnWorldHeights) {
  HeightfieldTileSettings s;
  s.columns = 33;
  s.cell = 0.05;
  s.origin_x = 3.0;
  s.origin_y = -2.0;
  s.min_height = 0.5;
  s.max_height = 2.5;
  s.initial_height = 1.25;
  HeightfieldTile tile(s);
  const double r = 0.1;
  // Centre of the tile, where the ground is flat at 1.25 m: the ball rests at 1.25 + r
  // (Bullet's contact margin lets it sink at most a few mm).
  const double z = rest_height_of_ball_on(tile, 3.8, -1.2, r);
  EXPECT_NEAR(z, 1.25 + r, 0.005);
}

TEST(HeightfieldTile, EditsAreSeenInPlaceAndClamped) {
  HeightfieldTileSettings s;
  s.columns = 33;
  s.cell = 0.05;
  HeightfieldTile tile(s);
  for (int j = 0; j < 33; ++j)
    for (int i = 0; i < 33; ++i) EXPECT_TRUE(tile.set_height(i, j, 0.4));
  EXPECT_FALSE(tile.set_height(0, 0, 5.0));
  EXPECT_FLOAT_EQ(static_cast<float>(tile.height(0, 0)), 1.0f);
  tile.set_height(0, 0, 0.4);
  EXPECT_NEAR(rest_height_of_ball_on(tile, 0.8, 0.8, 0.1), 0.5, 0.005);
}

TEST(HeightfieldTile, BadSettingsAreRejected) {
  HeightfieldTileSettings s;
  s.columns = 1;
  EXPECT_THROW(HeightfieldTile{s}, shore::InvalidSetting);
  s = {};
  s.max_height = s.min_height;
  EXPECT_THROW(HeightfieldTile{s}, shore::InvalidSetting);
  s = {};
  s.cell = std::nan("");
  EXPECT_THROW(HeightfieldTile{s}, shore::InvalidSetting);
}

TEST(Precision, LibraryAndApplicationAgree) {
  EXPECT_EQ(built_with_double_precision(), sizeof(btScalar) == sizeof(double));
}
