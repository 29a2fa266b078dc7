#pragma once
// A Bullet dynamics world that owns its parts, its bodies, their shapes and constraints:
// the one world owner of every scene, reference case and test. Z up unless a ground frame
// says otherwise (gravity then points down the frame's up: a Y-up world for
// bullet::GroundFrame::y_up()). A Featherstone world (Dynamics::featherstone: a
// btMultiBodyDynamicsWorld with Bullet's multibody solver) also owns btMultiBodys, their
// link colliders and multibody constraints (motors); a rigid world is exactly the
// btDiscreteDynamicsWorld it always was.

#include <memory>
#include <utility>
#include <vector>

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>
#include <btBulletDynamicsCommon.h>

#include "shore/bullet/ground_frame.h"

namespace shore::scenes {

/// The kind of Bullet world: rigid bodies only, or rigid bodies and btMultiBodys.
enum class Dynamics { rigid, featherstone };

class World {
 public:
  /// gravity: m/s^2 along -ground.up().
  explicit World(double gravity = 9.81, const bullet::GroundFrame& ground = {}, Dynamics dynamics = Dynamics::rigid);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  [[nodiscard]] btDiscreteDynamicsWorld& world() noexcept { return *world_; }
  [[nodiscard]] const btDiscreteDynamicsWorld& world() const noexcept { return *world_; }

  /// A rigid body owned by this world, with its shape (mass 0: static; kinematic bodies
  /// are static ones flagged CF_KINEMATIC_OBJECT).
  btRigidBody* add_body(std::unique_ptr<btCollisionShape> shape, double mass, const btVector3& position,
                        const btQuaternion& rotation = btQuaternion::getIdentity()) {
    return add_body(std::move(shape), mass, btTransform(rotation, position));
  }
  btRigidBody* add_body(std::unique_ptr<btCollisionShape> shape, double mass, const btTransform& pose);
  /// Keeps a shape alive as long as the world (the children of a compound shape).
  btCollisionShape* keep(std::unique_ptr<btCollisionShape> shape);
  /// Adds a constraint owned by this world; true: the two bodies do not collide.
  btTypedConstraint* add_constraint(std::unique_ptr<btTypedConstraint> constraint,
                                    bool disable_collisions_between_linked_bodies);

  /// A btMultiBody owned by this world, added to it (a Featherstone world only, else
  /// InvalidSetting). Build it complete (links set up, finalizeMultiDof called) first.
  btMultiBody* add_multibody(std::unique_ptr<btMultiBody> body);
  /// The collider of the multibody's `link` (-1: its base) with its shape, posed where the
  /// multibody's current joint positions put it and added to the world.
  btMultiBodyLinkCollider* add_collider(btMultiBody* body, int link, std::unique_ptr<btCollisionShape> shape);
  /// A multibody constraint (a joint motor, a limit) owned by this world, added to it.
  btMultiBodyConstraint* add_multibody_constraint(std::unique_ptr<btMultiBodyConstraint> constraint);
  /// The Featherstone world, or null for a rigid one.
  [[nodiscard]] btMultiBodyDynamicsWorld* featherstone() noexcept { return featherstone_; }
  /// The multibodies added, in order.
  [[nodiscard]] const std::vector<btMultiBody*>& multibodies() const noexcept { return multibody_list_; }

  /// Where the ground lies in this world (the couplings of its scenes use the same).
  [[nodiscard]] const bullet::GroundFrame& ground() const noexcept { return ground_; }
  /// A pose given in the ground's coordinates, in the world's.
  [[nodiscard]] btTransform to_world(const btTransform& ground_pose) const { return ground_.to_world() * ground_pose; }

  /// One fixed substep h (one internal step).
  void step(double h) { world_->stepSimulation(btScalar(h), 1, btScalar(h)); }

  /// The bodies added, in order.
  [[nodiscard]] const std::vector<btRigidBody*>& bodies() const noexcept { return body_list_; }

 private:
  bullet::GroundFrame ground_;
  std::unique_ptr<btDefaultCollisionConfiguration> config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btDbvtBroadphase> broadphase_;
  std::unique_ptr<btSequentialImpulseConstraintSolver> solver_;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btDefaultMotionState>> motions_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
  std::vector<btRigidBody*> body_list_;
  std::vector<std::unique_ptr<btTypedConstraint>> constraints_;
  btMultiBodyDynamicsWorld* featherstone_ = nullptr;  ///< world_ as one, or null
  /// Throws InvalidSetting naming `what` in a rigid world.
  void require_featherstone(const char* what) const;
  std::vector<std::unique_ptr<btMultiBody>> multibodies_;
  std::vector<btMultiBody*> multibody_list_;
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> colliders_;
  std::vector<std::unique_ptr<btMultiBodyConstraint>> multibody_constraints_;
};

}  // namespace shore::scenes
