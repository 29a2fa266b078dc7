#pragma once
// Reference cases for raycast wheels: a RaycastCar towed over flat soil at a held speed,
// free rolling (a stock vehicle or a SoilVehicle) or with every wheel held at a slip's spin
// (a SoilVehicle), measured on its front wheels, which meet fresh soil; and a SoilVehicle
// driving on soil, timed against the same car on a plain Bullet plane. Written once for the
// tests and the benchmark.

#include <cstdint>

#include "shore/scenes/raycast_car.h"
#include "shore/terrain/material.h"

namespace shore::scenes {

struct RaycastTowCase {
  terrain::Material material = terrain::Material::sand();
  double cell = 0.02;            ///< m
  double substep = 1.0 / 240.0;  ///< s
  RaycastCarSettings car;        ///< the car
  /// m: released this far above where its wheels touch the ground at rest length. How the
  /// car settled changes the rut it leaves (docs/terrain.md, "Raycast wheels").
  double drop = 0.0;
  double speed = 1.0;               ///< m/s, the chassis' forward speed, held
  double seconds = 3.0;             ///< s towed, after 1 s of settling
  double average_from = 1.0 / 3.0;  ///< share of the tow after which the means are taken
  double slip = -1.0;  ///< every wheel held at this slip's spin (needs car.soil_traction); < 0: free rolling
  bool soil_raycaster =
      true;  ///< the car casts with Shore's SoilRaycaster (its wheels rise); false: Bullet's stock one
};

/// Means over the front wheels after `average_from` of the tow.
struct RaycastTowResult {
  double load = 0.0;        ///< N, suspension force
  double resistance = 0.0;  ///< N, the columns' compaction push along the heading (negative: resists)
  double thrust = 0.0;      ///< N, the soil's shear along the heading (a SoilVehicle; 0 for a stock one)
  double pull = 0.0;        ///< N, thrust + resistance: the drawbar pull
  double torque = 0.0;      ///< N m, the shear's moment about the axle (a SoilVehicle)
  double slip = 0.0;        ///< Wong's i measured (a SoilVehicle)
  double sinkage = 0.0;     ///< m, the contact point's depth below the untouched surface (0)
  double rut = 0.0;         ///< m, mean depth of wheel 0's rut between the axles at the end
};
RaycastTowResult run_raycast_tow(const RaycastTowCase& c);

/// A four-wheel-drive SoilVehicle (the default RaycastCar: 800 kg, D 0.8 m, b 0.3 m)
/// accelerating on flat soil, and the same car on a Bullet static plane.
struct RaycastCostCase {
  terrain::Material material = terrain::Material::sand();
  double cell = 0.01;            ///< m
  double substep = 1.0 / 240.0;  ///< s
  double seconds = 2.0;          ///< s driven (after 0.5 s of settling)
  double engine_force = 500.0;   ///< N per wheel
  bool on_plane = false;         ///< drive on a static plane, no Shore
};
struct RaycastCostResult {
  double wall_seconds = 0.0;  ///< of the driven part, every world step included
  std::int64_t substeps = 0;
  double distance = 0.0;  ///< m driven
};
RaycastCostResult run_raycast_cost(const RaycastCostCase& c);

}  // namespace shore::scenes
