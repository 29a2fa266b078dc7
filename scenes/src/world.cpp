#include "shore/scenes/world.h"

namespace shore::scenes {

World::World(double gravity, const bullet::GroundFrame& ground)
    : ground_(ground),
      config_(std::make_unique<btDefaultCollisionConfiguration>()),
      dispatcher_(std::make_unique<btCollisionDispatcher>(config_.get())),
      broadphase_(std::make_unique<btDbvtBroadphase>()),
      solver_(std::make_unique<btSequentialImpulseConstraintSolver>()),
      world_(std::make_unique<btDiscreteDynamicsWorld>(dispatcher_.get(), broadphase_.get(), solver_.get(),
                                                       config_.get())) {
  ground_.validate("scenes.World(ground)");
  // Z up exactly as before (no product with the frame's up, whose rounding a tilted frame has).
  world_->setGravity(ground_.identity() ? btVector3(0, 0, btScalar(-gravity)) : ground_.up() * btScalar(-gravity));
}

World::~World() {
  for (auto& c : constraints_) world_->removeConstraint(c.get());
  for (auto& body : bodies_) world_->removeRigidBody(body.get());
}

btRigidBody* World::add_body(std::unique_ptr<btCollisionShape> shape, double mass, const btTransform& pose) {
  btVector3 inertia(0, 0, 0);
  if (mass > 0) shape->calculateLocalInertia(btScalar(mass), inertia);
  motions_.push_back(std::make_unique<btDefaultMotionState>(pose));
  btRigidBody::btRigidBodyConstructionInfo info(btScalar(mass), motions_.back().get(), shape.get(), inertia);
  bodies_.push_back(std::make_unique<btRigidBody>(info));
  shapes_.push_back(std::move(shape));
  world_->addRigidBody(bodies_.back().get());
  body_list_.push_back(bodies_.back().get());
  return bodies_.back().get();
}

btCollisionShape* World::keep(std::unique_ptr<btCollisionShape> shape) {
  shapes_.push_back(std::move(shape));
  return shapes_.back().get();
}

btTypedConstraint* World::add_constraint(std::unique_ptr<btTypedConstraint> constraint,
                                         bool disable_collisions_between_linked_bodies) {
  world_->addConstraint(constraint.get(), disable_collisions_between_linked_bodies);
  constraints_.push_back(std::move(constraint));
  return constraints_.back().get();
}

}  // namespace shore::scenes
