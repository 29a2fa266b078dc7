#pragma once
// The four-wheel vehicle of the vehicle scene and the slope-climbing case: a 400 kg chassis
// on four 0.6 m wheels (25 kg each) driven by hinge motors. Built once, here.

#include <array>
#include <span>

#include <btBulletDynamicsCommon.h>

#include "shore/bullet/terrain_coupling.h"
#include "shore/scenes/world.h"

namespace shore::scenes {

struct FourWheelerSettings {
  double wheel_radius = 0.3;    ///< m
  double wheel_width = 0.25;    ///< m
  double wheel_mass = 25.0;     ///< kg
  double chassis_mass = 400.0;  ///< kg
  double motor_torque = 600.0;  ///< N m per wheel, the most a motor gives
  double target_speed = 2.0;    ///< m/s: the motors aim for omega r = target_speed
};

struct FourWheeler {
  btRigidBody* chassis = nullptr;
  std::array<btRigidBody*, 4> wheels{};  ///< front left, front right, rear left, rear right
  std::array<btHingeConstraint*, 4> hinges{};
};

/// Builds the vehicle with its chassis centre at `at`, rotated by `tilt` (a slope: about
/// y), wheels added to every coupling given. `substep` sets the motors' impulse per substep.
FourWheeler build_four_wheeler(World& world, const FourWheelerSettings& s, const btVector3& at,
                               const btQuaternion& tilt, double substep,
                               std::span<bullet::TerrainCoupling* const> couplings);

}  // namespace shore::scenes
