#include "shore/scenes/four_wheeler.h"

#include <memory>

namespace shore::scenes {

FourWheeler build_four_wheeler(World& world, const FourWheelerSettings& s, const btVector3& at,
                               const btQuaternion& tilt, double substep,
                               std::span<bullet::TerrainCoupling* const> couplings) {
  FourWheeler v;
  v.chassis = world.add_body(std::make_unique<btBoxShape>(btVector3(1.0f, 0.5f, 0.15f)), s.chassis_mass, at, tilt);
  v.chassis->setActivationState(DISABLE_DEACTIVATION);
  const std::array<btVector3, 4> mounts = {btVector3(0.75f, 0.65f, -0.25f), btVector3(0.75f, -0.65f, -0.25f),
                                           btVector3(-0.75f, 0.65f, -0.25f), btVector3(-0.75f, -0.65f, -0.25f)};
  const btMatrix3x3 turn(tilt);
  for (int k = 0; k < 4; ++k) {
    const btVector3& mount = mounts[static_cast<std::size_t>(k)];
    btRigidBody* wheel =
        world.add_body(std::make_unique<btCylinderShape>(
                           btVector3(btScalar(s.wheel_radius), btScalar(s.wheel_width / 2), btScalar(s.wheel_radius))),
                       s.wheel_mass, at + turn * mount, tilt);
    wheel->setActivationState(DISABLE_DEACTIVATION);
    wheel->setFriction(1.0f);
    auto hinge = std::make_unique<btHingeConstraint>(*v.chassis, *wheel, mount, btVector3(0, 0, 0), btVector3(0, 1, 0),
                                                     btVector3(0, 1, 0));
    // Bullet's hinge motor drives the velocity of body A (chassis) relative to body B
    // (wheel) about the axis; the wheel rolls forward (+x) spinning at +v/R about +y
    // relative to the chassis, so the target is -v/R.
    hinge->enableAngularMotor(true, btScalar(-s.target_speed / s.wheel_radius), btScalar(s.motor_torque * substep));
    v.hinges[static_cast<std::size_t>(k)] =
        static_cast<btHingeConstraint*>(world.add_constraint(std::move(hinge), true));
    for (bullet::TerrainCoupling* c : couplings) c->add_body(wheel);
    v.wheels[static_cast<std::size_t>(k)] = wheel;
  }
  return v;
}

}  // namespace shore::scenes
