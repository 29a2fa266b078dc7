#pragma once
// What both couplings promise about bad bodies: add_body refuses, with InvalidSetting, a
// shape no envelope can take; a body whose pose breaks later (not a rotation) is skipped
// and counted inside stepSimulation, which goes on.
#include <gtest/gtest.h>

#include <memory>

#include <BulletCollision/CollisionShapes/btMultiSphereShape.h>
#include <btBulletDynamicsCommon.h>

#include "shore/core/error.h"
#include "shore/scenes/world.h"

/// A body whose shape the envelope rasterizer does not support.
inline btRigidBody* add_unsupported_body(shore::scenes::World& world) {
  btVector3 centres[1] = {btVector3(0, 0, 0)};
  btScalar radii[1] = {btScalar(0.1)};
  return world.add_body(std::make_unique<btMultiSphereShape>(centres, radii, 1), 5.0, btVector3(0, 0, 1));
}

/// `coupling` (a TerrainCoupling or a WaterCoupling in `world`) refuses an unsupported
/// shape and skips a kinematic box at `at` once its pose is sheared.
template <class Coupling>
void expect_bad_bodies_refused_or_skipped(shore::scenes::World& world, Coupling& coupling, const btVector3& at) {
  EXPECT_THROW(coupling.add_body(add_unsupported_body(world)), shore::InvalidSetting);
  // A kinematic body takes its pose from its motion state as it is, sheared or not.
  btRigidBody* box = world.add_body(std::make_unique<btBoxShape>(btVector3(0.1f, 0.1f, 0.1f)), 0.0, at);
  box->setCollisionFlags(box->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
  box->setActivationState(DISABLE_DEACTIVATION);
  coupling.add_body(box);
  btTransform sheared = box->getWorldTransform();
  sheared.getBasis()[0][1] = btScalar(0.5);  // not a rotation
  box->getMotionState()->setWorldTransform(sheared);
  EXPECT_NO_THROW(for (int s = 0; s < 4; ++s) world.step(1.0 / 240));
  EXPECT_GT(coupling.stats().skipped_bodies, 0);
  // Farther than 1e9 m from the origin no column index is representable (the sanitizer
  // run caught the conversion overflowing): skipped and counted like a broken pose.
  const auto skipped = coupling.stats().skipped_bodies;
  btTransform far = btTransform::getIdentity();
  far.setOrigin(btVector3(btScalar(2e9), btScalar(-3e12), btScalar(0.3)));
  box->getMotionState()->setWorldTransform(far);
  EXPECT_NO_THROW(for (int s = 0; s < 4; ++s) world.step(1.0 / 240));
  EXPECT_GT(coupling.stats().skipped_bodies, skipped);
}
