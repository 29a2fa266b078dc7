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
