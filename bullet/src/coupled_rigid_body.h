#pragma once
// Internal: a btRigidBody as a coupled body.

#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <LinearMath/btTransformUtil.h>

#include "coupled_body.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

class CoupledRigidBody final : public CoupledBody {
 public:
  explicit CoupledRigidBody(btRigidBody& body) noexcept : CoupledBody(body), body_(&body) {}

  [[nodiscard]] btRigidBody& rigid_body() const noexcept { return *body_; }
  [[nodiscard]] bool dynamic() const override { return !body_->isStaticOrKinematicObject(); }
  [[nodiscard]] Motion motion() const override {
    return {body_->getLinearVelocity(), body_->getAngularVelocity(), body_->getCenterOfMassPosition()};
  }
  [[nodiscard]] double inverse_mass() const override { return body_->getInvMass(); }
  [[nodiscard]] btMatrix3x3 inverse_inertia() const override { return body_->getInvInertiaTensorWorld(); }
  /// A body Bullet holds to some axes (its linear and angular factors, which scale every
  /// impulse applied to it) answers an impulse with its mobility scaled by them, as Bullet
  /// moves it: the soil's solve then never counts on a motion Bullet will not make (a rig's
  /// wheel held to its plane sliding sideways or tilting). Free bodies keep the plain path.
  [[nodiscard]] bool mobility(double a[6][6]) const override {
    const btVector3 lf = body_->getLinearFactor(), af = body_->getAngularFactor();
    if (lf == btVector3(1, 1, 1) && af == btVector3(1, 1, 1)) return false;
    const btMatrix3x3 inv = body_->getInvInertiaTensorWorld();
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) a[r][c] = 0.0;
    for (int k = 0; k < 3; ++k) a[k][k] = double(lf[k]) * body_->getInvMass();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) a[3 + r][3 + c] = double(af[r]) * double(inv[r][c]) * double(af[c]);
    return true;
  }
  void apply_impulse(const btVector3& impulse, const btVector3& angular_impulse) override {
    body_->applyCentralImpulse(impulse);
    body_->applyTorqueImpulse(angular_impulse);
  }
  void correct_motion(const btVector3& linear, const btVector3& angular, double h) override {
    const btVector3 v0 = body_->getLinearVelocity(), w0 = body_->getAngularVelocity();
    body_->setLinearVelocity(linear);
    body_->setAngularVelocity(angular);
    const btVector3 dv = body_->getLinearVelocity() - v0, dw = body_->getAngularVelocity() - w0;
    btTransform corrected;
    btTransformUtil::integrateTransform(body_->getCenterOfMassTransform(), dv, dw, btScalar(h), corrected);
    body_->setCenterOfMassTransform(corrected);
  }
  void stop(double h) override {
    const btVector3 v0 = body_->getLinearVelocity(), w0 = body_->getAngularVelocity();
    body_->setLinearVelocity(btVector3(0, 0, 0));
    body_->setAngularVelocity(btVector3(0, 0, 0));
    btTransform corrected;
    btTransformUtil::integrateTransform(body_->getCenterOfMassTransform(), -v0, -w0, btScalar(h), corrected);
    body_->setCenterOfMassTransform(corrected);
  }
  void set_linear_velocity(const btVector3& linear) override { body_->setLinearVelocity(linear); }
  void translate(const btVector3& offset) override {
    btTransform t = body_->getCenterOfMassTransform();
    t.setOrigin(t.getOrigin() + offset);
    body_->setCenterOfMassTransform(t);
  }

 private:
  btRigidBody* body_;
};

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
