#pragma once
// A btRaycastVehicle whose wheels take their traction and side force from Shore's soil.
//
// A stock btRaycastVehicle added to a TerrainCoupling (add_vehicle) sinks into the soil and
// meets its compaction resistance, but grips with Bullet's Coulomb friction (m_frictionSlip
// times the suspension force, whatever the ground). A SoilVehicle is the same vehicle (the
// same constructor, tuning, wheels, engine force, brake and steering) whose wheels on soft
// Shore ground grip as the soil does instead: the shear strength of the soil under the rim,
// c + sigma tan(phi), mobilised with slip (Janosi-Hanamoto, with Wong and Reece's shear
// displacement along the rim), longitudinal and lateral slip sharing one strength. Wheels
// on anything else (rigid Shore ground, other bodies) keep Bullet's friction.
//
//   auto* car = new shore::bullet::SoilVehicle(tuning, chassis, raycaster);  // was btRaycastVehicle
//   world->addVehicle(car);                      // as before
//   ground.add_vehicle(car, widths);             // each wheel's width, m
//
// Units and conventions: Bullet's. The engine force (applyEngineForce) is the force the
// wheel's torque gives at its rim, N; the brake (setBrake) is, as in Bullet, an impulse per
// substep, N s: the brake resists the wheel's spin with up to brake / substep N at the rim.
// A wheel's spin is not integrated (a raycast wheel has no inertia in Bullet): each substep
// it is the spin at which the soil's shear balances the engine force less the brake; a wheel
// driven harder than the soil can take spins (slip up to about 0.8), a braked wheel the soil
// cannot turn locks. The wheel's m_rotation follows that spin.

#include <limits>
#include <memory>
#include <vector>

#include <BulletDynamics/Vehicle/btRaycastVehicle.h>

#include "shore/bullet/config.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

namespace coupling_detail {
class RaycastWheels;
struct SoftGround;
struct SoilVehicleState;
}  // namespace coupling_detail

/// What the soil did to one wheel of a SoilVehicle in the last substep (all zero, on_soil
/// false, for a wheel not on soft Shore ground).
struct WheelTraction {
  bool on_soil = false;
  double spin = 0.0;  ///< rad/s, positive rolling forward
  /// Wong's i: 1 - v / (omega r) when driving (0..1; 1 for a wheel driven against the
  /// motion), omega r / v - 1 when braking (-1..0).
  double slip = 0.0;
  double forward = 0.0;     ///< N, the soil's shear on the chassis along the wheel's heading (thrust)
  double side = 0.0;        ///< N, the soil's shear on the chassis along the wheel's axle
  double torque = 0.0;      ///< N m, the shear's moment about the axle: the torque driving the wheel takes
  double resistance = 0.0;  ///< N, the columns' compaction push along the heading (negative: resists)
};

class SoilVehicle : public btRaycastVehicle {
 public:
  using btRaycastVehicle::btRaycastVehicle;

  /// Bullet's friction for the wheels not on soft ground of the coupling this vehicle was
  /// added to; the coupling gives the others theirs.
  void updateFriction(btScalar timeStep) override;

  /// Holds wheel `wheel` at `spin` rad/s on soft ground, as a speed-controlled motor strong
  /// enough to hold it (a test rig, a robot's wheel servo), instead of balancing its engine
  /// force; release_wheel_spin gives it back to the engine force. Throws InvalidSetting for a
  /// wheel index out of range or a spin that is not finite.
  void hold_wheel_spin(int wheel, double spin);
  void release_wheel_spin(int wheel);

  /// The last substep's soil traction on `wheel` (a zero readout for a bad index).
  [[nodiscard]] const WheelTraction& wheel_traction(int wheel) const;

 private:
  friend class coupling_detail::RaycastWheels;
  friend struct coupling_detail::SoilVehicleState;  // checkpoints (vehicle_state.cpp)
  struct WheelSoil {
    WheelTraction last;
    double held_spin = std::numeric_limits<double>::quiet_NaN();  ///< rad/s, NaN: not held
  };
  WheelSoil& soil(int wheel);
  [[nodiscard]] bool on_soft_ground(const btVector3& world_point) const;
  std::vector<WheelSoil> soil_;
  /// The soft ground of each coupling this vehicle is added to (expires with the coupling).
  std::vector<std::weak_ptr<const coupling_detail::SoftGround>> grounds_;
};

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
