#pragma once
// A car built the way Bullet's own VehicleDemo builds one: a box chassis carried by a stock
// btRaycastVehicle with btDefaultVehicleRaycaster (up and forward: the ground's z and x). Written once for the
// tests, the rally scene and the benchmarks. The one thing in it that knows Shore is the
// choice of vehicle class: a stock btRaycastVehicle, or Shore's SoilVehicle (the same vehicle,
// gripping as the soil does).

#include <memory>

#include <BulletDynamics/Vehicle/btRaycastVehicle.h>
#include <btBulletDynamicsCommon.h>

#include "shore/bullet/soil_raycaster.h"
#include "shore/scenes/world.h"

namespace shore::scenes {

struct RaycastCarSettings {
  double mass = 800.0;                 ///< kg, the chassis (the wheels have none of their own)
  double half_length = 1.8;            ///< m, chassis box half extent along x (forward)
  double half_width = 0.8;             ///< m, along y
  double half_height = 0.3;            ///< m, along z
  double wheel_radius = 0.4;           ///< m
  double wheel_width = 0.3;            ///< m (Bullet's vehicle ignores it; Shore's soil needs it)
  double axle_offset = 1.3;            ///< m from the chassis centre to each axle, along x
  double track_half = 0.75;            ///< m from the centre line to each wheel, along y
  double connection_height = -0.1;     ///< m, where the suspension hangs, below the chassis centre
  double suspension_rest = 0.45;       ///< m, suspension rest length
  double suspension_stiffness = 20.0;  ///< Bullet's tuning: spring per unit chassis mass, 1/s^2
  double damping_compression = 2.3;    ///< Bullet's tuning (about 0.3 of critical)
  double damping_relaxation = 4.4;     ///< Bullet's tuning (about 0.5 of critical)
  double friction_slip = 1.0;          ///< Bullet's Coulomb friction of each wheel on rigid ground
  double max_suspension_travel_cm = 50.0;
  /// Build a shore::bullet::SoilVehicle (traction and side force from the soil's shear on
  /// Shore's soft ground) instead of a stock btRaycastVehicle (Bullet's friction everywhere).
  bool soil_traction = false;
  bool four_wheel_drive = false;  ///< the engine force on every wheel, not only the rear ones
};

class RaycastCar {
 public:
  /// Adds the chassis to world (its centre at `at`, heading along +x, up along z, all in the
  /// world's ground frame: World::ground()) and the vehicle as an action; both are taken
  /// out of the world again by the destructor.
  /// With `soil` (a coupling of this world) the vehicle casts its rays with Shore's
  /// SoilRaycaster on it (pass soil_raycaster() to its add_vehicle); null: Bullet's stock
  /// btDefaultVehicleRaycaster.
  RaycastCar(World& world, const RaycastCarSettings& settings, const btVector3& at,
             bullet::TerrainCoupling* soil = nullptr);
  ~RaycastCar();
  RaycastCar(const RaycastCar&) = delete;
  RaycastCar& operator=(const RaycastCar&) = delete;

  /// Engine force (N, per driven wheel: the rear ones, or all four), brake (Bullet's: N s per
  /// substep, per wheel) and steering angle of the
  /// front wheels (rad, positive to the left), held until set again.
  void drive(double engine_force, double brake, double steering);

  [[nodiscard]] btRaycastVehicle& vehicle() noexcept { return *vehicle_; }
  [[nodiscard]] const btRaycastVehicle& vehicle() const noexcept { return *vehicle_; }
  [[nodiscard]] btRigidBody* chassis() const noexcept { return chassis_; }
  [[nodiscard]] const RaycastCarSettings& settings() const noexcept { return settings_; }
  /// The SoilRaycaster the vehicle was built with, or null (the stock raycaster).
  [[nodiscard]] const bullet::SoilRaycaster* soil_raycaster() const noexcept { return soil_raycaster_; }
  /// Wheels whose ray found ground in the last step.
  [[nodiscard]] int wheels_on_ground() const;

 private:
  World& world_;
  RaycastCarSettings settings_;
  btRigidBody* chassis_ = nullptr;
  std::unique_ptr<btVehicleRaycaster> raycaster_;
  bullet::SoilRaycaster* soil_raycaster_ = nullptr;  ///< raycaster_ if it is one
  std::unique_ptr<btRaycastVehicle> vehicle_;
};

}  // namespace shore::scenes
