#pragma once
// Internal: one Bullet object a coupling serves, as the couplings see it. What a coupling
// needs of it is where it is (its collision object's shape and pose), how it moves, how an
// impulse changes that, and a key that names it from step to step. A btRigidBody is one
// kind (coupled_rigid_body.h); a btMultiBody link, a raycast wheel or a kinematic character
// are others, each implementing these the way its Bullet object moves.

#include <cstdint>

#include <BulletCollision/BroadphaseCollision/btBroadphaseProxy.h>
#include <BulletCollision/CollisionDispatch/btCollisionObject.h>
#include <LinearMath/btMatrix3x3.h>
#include <LinearMath/btTransform.h>

#include "shore/bullet/config.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

/// How a body moves: a point p of it moves at linear + angular x (p - centre). Like every
/// quantity below, in the coupling's ground coordinates.
struct Motion {
  btVector3 linear{0, 0, 0};   ///< m/s, of the centre of mass
  btVector3 angular{0, 0, 0};  ///< rad/s
  btVector3 centre{0, 0, 0};   ///< m, the centre of mass
};

class CoupledBody {
 public:
  virtual ~CoupledBody() = default;
  CoupledBody(const CoupledBody&) = delete;
  CoupledBody& operator=(const CoupledBody&) = delete;

  /// The collision object Bullet knows the body by. Its address is the body's identity; it
  /// is read only while the world holds it (BodyRegistry::forget_lost).
  [[nodiscard]] btCollisionObject& object() const noexcept { return *object_; }
  [[nodiscard]] const btCollisionShape* shape() const noexcept { return object_->getCollisionShape(); }
  /// Where it is, in the coupling's ground coordinates (ground_frame.h; the world's
  /// unless a framed body says otherwise).
  [[nodiscard]] virtual btTransform pose() const { return object_->getWorldTransform(); }
  /// The object the world holds for the body: its own, or for a part of another (a raycast
  /// wheel: its vehicle's chassis) that one. It is asleep or awake, in the world or lost.
  [[nodiscard]] btCollisionObject& held() const noexcept { return *held_; }
  [[nodiscard]] btBroadphaseProxy* proxy() const noexcept { return held_->getBroadphaseHandle(); }
  [[nodiscard]] bool awake() const noexcept { return held_->isActive(); }
  void wake() const { held_->activate(true); }
  /// Names the body from step to step whatever the order bodies were added in: its
  /// broadphase proxy's id, given in the order objects joined the world. 0 outside a world.
  [[nodiscard]] std::uint64_t key() const noexcept {
    return proxy() != nullptr ? static_cast<std::uint64_t>(proxy()->m_uniqueId) : 0;
  }

  /// Forces move it, so the couplings push it with impulses. False: the game moves it
  /// (kinematic or static), and it presses the terrain by its shape alone.
  [[nodiscard]] virtual bool dynamic() const = 0;
  [[nodiscard]] virtual Motion motion() const = 0;
  /// 1/kg and the world-frame inverse inertia tensor about the centre of mass.
  [[nodiscard]] virtual double inverse_mass() const = 0;
  [[nodiscard]] virtual btMatrix3x3 inverse_inertia() const = 0;
  /// A body whose response to an impulse is not its own mass's (a btMultiBody link: the
  /// whole articulation answers) gives its 6 x 6 mobility ((P, L) to (dv, dw)) and returns
  /// true; a free rigid body returns false (inverse_mass and inverse_inertia say it all).
  [[nodiscard]] virtual bool mobility(double a[6][6]) const {
    (void)a;
    return false;
  }
  /// Adds an impulse (N s) and an angular impulse about the centre of mass (N m s).
  virtual void apply_impulse(const btVector3& impulse, const btVector3& angular_impulse) = 0;
  /// Gives the body these velocities and moves this substep's pose by what the change of
  /// velocity would have moved it over h: a correction of the substep Bullet integrated.
  virtual void correct_motion(const btVector3& linear, const btVector3& angular, double h) = 0;
  /// Stops the body: zero velocities, and this substep's pose moved back by what its
  /// velocities moved it over h.
  virtual void stop(double h) = 0;
  /// Sets the linear velocity alone.
  virtual void set_linear_velocity(const btVector3& linear) = 0;
  /// Moves the body by `offset` (m) without changing its velocities.
  virtual void translate(const btVector3& offset) = 0;

 protected:
  explicit CoupledBody(btCollisionObject& object) noexcept : object_(&object), held_(&object) {}
  CoupledBody(btCollisionObject& object, btCollisionObject& held) noexcept : object_(&object), held_(&held) {}

 private:
  btCollisionObject* object_;
  btCollisionObject* held_;
};

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
