#pragma once
// A plain Bullet dynamics world (Z up) that owns its parts: the boilerplate every scene,
// test and benchmark would otherwise repeat.

#include <memory>
#include <vector>

#include <btBulletDynamicsCommon.h>

namespace shore::cases {

class BulletWorld {
 public:
  explicit BulletWorld(double gravity = 9.81);
  ~BulletWorld();
  BulletWorld(const BulletWorld&) = delete;
  BulletWorld& operator=(const BulletWorld&) = delete;

  btDiscreteDynamicsWorld& world() noexcept { return *world_; }

  /// A rigid body owned by this world (mass 0: static). Pose: position and Euler angles
  /// (roll, pitch, yaw) in radians; the shape is owned too.
  btRigidBody* add_body(std::unique_ptr<btCollisionShape> shape, double mass, const btVector3& position,
                        const btQuaternion& rotation = btQuaternion::getIdentity());
  /// One fixed substep h (one internal step).
  void step(double h) { world_->stepSimulation(btScalar(h), 1, btScalar(h)); }

 private:
  std::unique_ptr<btDefaultCollisionConfiguration> config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btDbvtBroadphase> broadphase_;
  std::unique_ptr<btSequentialImpulseConstraintSolver> solver_;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btDefaultMotionState>> motions_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
};

}  // namespace shore::cases
