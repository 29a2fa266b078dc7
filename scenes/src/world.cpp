#include "shore/scenes/world.h"

#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>

#include "shore/core/error.h"

namespace shore::scenes {
namespace {

std::unique_ptr<btSequentialImpulseConstraintSolver> make_solver(Dynamics dynamics) {
  if (dynamics == Dynamics::featherstone) return std::make_unique<btMultiBodyConstraintSolver>();
  return std::make_unique<btSequentialImpulseConstraintSolver>();
}

std::unique_ptr<btDiscreteDynamicsWorld> make_world(Dynamics dynamics, btCollisionDispatcher* dispatcher,
                                                    btDbvtBroadphase* broadphase,
                                                    btSequentialImpulseConstraintSolver* solver,
                                                    btDefaultCollisionConfiguration* config) {
  if (dynamics == Dynamics::featherstone)
    return std::make_unique<btMultiBodyDynamicsWorld>(dispatcher, broadphase,
                                                      static_cast<btMultiBodyConstraintSolver*>(solver), config);
  return std::make_unique<btDiscreteDynamicsWorld>(dispatcher, broadphase, solver, config);
}

}  // namespace

World::World(double gravity, const bullet::GroundFrame& ground, Dynamics dynamics)
    : ground_(ground),
      config_(std::make_unique<btDefaultCollisionConfiguration>()),
      dispatcher_(std::make_unique<btCollisionDispatcher>(config_.get())),
      broadphase_(std::make_unique<btDbvtBroadphase>()),
      solver_(make_solver(dynamics)),
      world_(make_world(dynamics, dispatcher_.get(), broadphase_.get(), solver_.get(), config_.get())) {
  if (dynamics == Dynamics::featherstone) featherstone_ = static_cast<btMultiBodyDynamicsWorld*>(world_.get());
  ground_.validate("scenes.World(ground)");
  // Z up exactly as before (no product with the frame's up, whose rounding a tilted frame has).
  world_->setGravity(ground_.identity() ? btVector3(0, 0, btScalar(-gravity)) : ground_.up() * btScalar(-gravity));
}

World::~World() {
  for (auto& c : multibody_constraints_) featherstone_->removeMultiBodyConstraint(c.get());
  for (auto& c : colliders_)
    if (c->getBroadphaseHandle() != nullptr) world_->removeCollisionObject(c.get());
  for (auto& mb : multibodies_) featherstone_->removeMultiBody(mb.get());
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

void World::require_featherstone(const char* what) const {
  if (featherstone_ == nullptr)
    throw InvalidSetting(what, "a rigid world", "multibodies need a World made with Dynamics::featherstone");
}

btMultiBody* World::add_multibody(std::unique_ptr<btMultiBody> body) {
  require_featherstone("scenes.World.add_multibody");
  featherstone_->addMultiBody(body.get());
  multibodies_.push_back(std::move(body));
  multibody_list_.push_back(multibodies_.back().get());
  return multibody_list_.back();
}

btMultiBodyLinkCollider* World::add_collider(btMultiBody* body, int link, std::unique_ptr<btCollisionShape> shape) {
  require_featherstone("scenes.World.add_collider");
  colliders_.push_back(std::make_unique<btMultiBodyLinkCollider>(body, link));
  btMultiBodyLinkCollider* c = colliders_.back().get();
  c->setCollisionShape(keep(std::move(shape)));
  if (link < 0)
    body->setBaseCollider(c);
  else
    body->getLink(link).m_collider = c;
  btAlignedObjectArray<btQuaternion> rotations;
  btAlignedObjectArray<btVector3> offsets;
  rotations.resize(body->getNumLinks() + 1);
  offsets.resize(body->getNumLinks() + 1);
  body->forwardKinematics(rotations, offsets);
  body->updateCollisionObjectWorldTransforms(rotations, offsets);
  world_->addCollisionObject(c, btBroadphaseProxy::DefaultFilter, btBroadphaseProxy::AllFilter);
  return c;
}

btMultiBodyConstraint* World::add_multibody_constraint(std::unique_ptr<btMultiBodyConstraint> constraint) {
  require_featherstone("scenes.World.add_multibody_constraint");
  featherstone_->addMultiBodyConstraint(constraint.get());
  multibody_constraints_.push_back(std::move(constraint));
  return multibody_constraints_.back().get();
}

}  // namespace shore::scenes
