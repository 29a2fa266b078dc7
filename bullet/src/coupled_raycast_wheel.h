#pragma once
// Internal: a btRaycastVehicle's wheel as a coupled body. The wheel has no body of its own:
// it is a cylinder (the wheel's radius, a width the game gives) at the pose its ray found
// (wheel_pose), fixed to the chassis. So it moves with the chassis, an impulse on it is an
// impulse on the chassis at the wheel, and the world holds it while it holds the chassis.
// The cylinder's collision object is the wheel's own, never added to the world: it names
// the wheel and carries its shape.

#include <memory>

#include <BulletCollision/CollisionShapes/btCylinderShape.h>
#include <BulletDynamics/Vehicle/btRaycastVehicle.h>

#include "coupled_rigid_body.h"
#include "raycast_wheels.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

class CoupledRaycastWheel final : public CoupledBody {
 public:
  /// Wheel k of the vehicle (a valid index, a checked width, m): a cylinder along its axle.
  static std::unique_ptr<CoupledRaycastWheel> make(btRaycastVehicle& vehicle, int k, double width) {
    const double r = double(vehicle.getWheelInfo(k).m_wheelsRadius);
    auto cylinder = std::make_unique<Cylinder>(btVector3(btScalar(width / 2), btScalar(r), btScalar(r)));
    return std::unique_ptr<CoupledRaycastWheel>(new CoupledRaycastWheel(vehicle, k, std::move(cylinder)));
  }

  [[nodiscard]] const btRaycastVehicle& vehicle() const noexcept { return *vehicle_; }
  [[nodiscard]] btTransform pose() const override { return wheel_pose(vehicle_->getWheelInfo(wheel_)); }
  [[nodiscard]] bool dynamic() const override { return chassis_.dynamic(); }
  [[nodiscard]] Motion motion() const override { return chassis_.motion(); }
  [[nodiscard]] double inverse_mass() const override { return chassis_.inverse_mass(); }
  [[nodiscard]] btMatrix3x3 inverse_inertia() const override { return chassis_.inverse_inertia(); }
  void apply_impulse(const btVector3& impulse, const btVector3& angular_impulse) override {
    chassis_.apply_impulse(impulse, angular_impulse);
  }
  void correct_motion(const btVector3& linear, const btVector3& angular, double h) override {
    chassis_.correct_motion(linear, angular, h);
  }
  void stop(double h) override { chassis_.stop(h); }
  void set_linear_velocity(const btVector3& linear) override { chassis_.set_linear_velocity(linear); }
  void translate(const btVector3& offset) override { chassis_.translate(offset); }

 private:
  /// The wheel's shape and the collision object that carries it (outside the world).
  struct Cylinder {
    explicit Cylinder(const btVector3& half_extents) : shape(half_extents) {
      shape.setMargin(btScalar(0));
      object.setCollisionShape(&shape);
    }
    btCylinderShapeX shape;
    btCollisionObject object;
  };

  CoupledRaycastWheel(btRaycastVehicle& vehicle, int k, std::unique_ptr<Cylinder> cylinder)
      : CoupledBody(cylinder->object, *vehicle.getRigidBody()),
        cylinder_(std::move(cylinder)),
        vehicle_(&vehicle),
        wheel_(k),
        chassis_(*vehicle.getRigidBody()) {}

  std::unique_ptr<Cylinder> cylinder_;
  btRaycastVehicle* vehicle_;
  int wheel_;
  CoupledRigidBody chassis_;
};

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
