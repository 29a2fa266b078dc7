#include "shore/cases/bullet_world.h"

namespace shore::cases {

BulletWorld::BulletWorld(double gravity)
    : config_(std::make_unique<btDefaultCollisionConfiguration>()),
      dispatcher_(std::make_unique<btCollisionDispatcher>(config_.get())),
      broadphase_(std::make_unique<btDbvtBroadphase>()),
      solver_(std::make_unique<btSequentialImpulseConstraintSolver>()),
      world_(std::make_unique<btDiscreteDynamicsWorld>(dispatcher_.get(), broadphase_.get(), solver_.get(),
                                                       config_.get())) {
  world_->setGravity(btVector3(0, 0, btScalar(-gravity)));
}

BulletWorld::~BulletWorld() {
  for (auto& body : bodies_) world_->removeRigidBody(body.get());
}

btRigidBody* BulletWorld::add_body(std::unique_ptr<btCollisionShape> shape, double mass, const btVector3& position,
                                   const btQuaternion& rotation) {
  btVector3 inertia(0, 0, 0);
  if (mass > 0) shape->calculateLocalInertia(btScalar(mass), inertia);
  motions_.push_back(std::make_unique<btDefaultMotionState>(btTransform(rotation, position)));
  btRigidBody::btRigidBodyConstructionInfo info(btScalar(mass), motions_.back().get(), shape.get(), inertia);
  bodies_.push_back(std::make_unique<btRigidBody>(info));
  shapes_.push_back(std::move(shape));
  world_->addRigidBody(bodies_.back().get());
  return bodies_.back().get();
}

}  // namespace shore::cases
