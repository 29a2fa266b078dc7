// A ball resting on a HeightfieldTile must rest where geometry says: on the tile's world
// heights, at the tile's world position (checks the placement rules of Bullet 3.24).
#include <gtest/gtest.h>

#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <memory>
#include <string>

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

namespace {
/// A 17 x 17 tile of 5 cm cells at 1.0 m, every vertex with an odd index raised 4 cm: a field
/// of ridges, whose even vertices all lie on the plane z = 1.
std::unique_ptr<HeightfieldTile> ridged_tile(int contact_stride) {
  HeightfieldTileSettings s;
  s.columns = 17;
  s.cell = 0.05;
  s.initial_height = 1.0;
  s.max_height = 2.0;
  s.contact_stride = contact_stride;
  auto tile = std::make_unique<HeightfieldTile>(s);
  for (int j = 0; j < s.columns; ++j)
    for (int i = 0; i < s.columns; ++i) tile->set_height(i, j, (i % 2 == 1 || j % 2 == 1) ? 1.04 : 1.0);
  return tile;
}

/// Where a ray straight down at (x, y) meets the tile.
double ray_height(HeightfieldTile& tile, double x, double y) {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  btDbvtBroadphase broadphase;
  btCollisionWorld world(&dispatcher, &broadphase, &config);
  world.addCollisionObject(tile.object());
  const btVector3 from(btScalar(x), btScalar(y), btScalar(3)), to(btScalar(x), btScalar(y), btScalar(-3));
  btCollisionWorld::ClosestRayResultCallback hit(from, to);
  world.rayTest(from, to, hit);
  world.removeCollisionObject(tile.object());
  return hit.hasHit() ? double(hit.m_hitPointWorld.z()) : std::nan("");
}
}  // namespace

// With a contact stride of 2 a ball meets only the even vertices' triangles, the plane
// z = 1, and rests on it; with every vertex it rests on the ridges. A ray sees every vertex
// whatever the stride: it finds a ridge's top.
TEST(HeightfieldTile, ContactStrideSamplesTheVerticesForContactsButNotForRays) {
  const double r = 0.1, x = 0.4, y = 0.4;  // the middle of the tile, a vertex with even indices
  const std::unique_ptr<HeightfieldTile> every = ridged_tile(1), sampled = ridged_tile(2);
  EXPECT_GT(rest_height_of_ball_on(*every, x, y, r), 1.0 + r + 0.02) << "m: on the ridges";
  EXPECT_NEAR(rest_height_of_ball_on(*sampled, x, y, r), 1.0 + r, 0.005) << "m: on the sampled plane";
  const double ridge_x = x + 0.05;  // an odd vertex
  EXPECT_NEAR(ray_height(*every, ridge_x, y), 1.04, 1e-5);
  EXPECT_NEAR(ray_height(*sampled, ridge_x, y), 1.04, 1e-5);
}

TEST(HeightfieldTile, ContactStrideMustDivideTheCells) {
  HeightfieldTileSettings s;
  s.columns = 17;
  for (const int bad : {0, -2, 3, 5}) {
    s.contact_stride = bad;
    try {
      HeightfieldTile tile(s);
      ADD_FAILURE() << "contact_stride " << bad << " was accepted";
    } catch (const shore::InvalidSetting& e) {
      EXPECT_NE(std::string(e.what()).find("contact_stride"), std::string::npos) << e.what();
    }
  }
  for (const int good : {1, 2, 4, 8, 16}) {
    s.contact_stride = good;
    EXPECT_NO_THROW(HeightfieldTile{s});
  }
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
