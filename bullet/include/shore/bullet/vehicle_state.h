#pragma once
// Saving and restoring a btRaycastVehicle's evolving state for a checkpoint, beside its
// chassis (save_bodies, shore/bullet/body_state.h) and Shore's couplings. What lasts from
// one step to the next in Bullet's vehicle is, per wheel, its rotation and last rotation
// step (Bullet keeps a wheel off the ground turning), the game's inputs (steering, engine
// force, brake) and what its last ray found (contact, load, directions: Shore's couplings
// read them in a substep before the vehicle casts again). A SoilVehicle adds, per wheel, the spin it is held at and its
// last substep's traction (the spray reads the last spin).
//
//   w.add("VEHICLE", shore::bullet::save_vehicle(car));
//   ...
//   shore::bullet::restore_vehicle(fresh_car, reader.section("VEHICLE"), reader.describe("VEHICLE"));
//
// The application rebuilds the vehicle the same way (the same class, wheels and tuning).

#include <span>
#include <string>
#include <vector>

#include <BulletDynamics/Vehicle/btRaycastVehicle.h>

#include "shore/bullet/config.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

[[nodiscard]] std::vector<unsigned char> save_vehicle(const btRaycastVehicle& vehicle);

/// Restores save_vehicle's bytes into a vehicle built the same way. FileError naming
/// `source` (the vehicle unchanged) for bytes truncated, corrupt or of another version or
/// precision, another wheel count, a stock vehicle's bytes for a SoilVehicle or the reverse,
/// or a value that is not finite.
void restore_vehicle(btRaycastVehicle& vehicle, std::span<const unsigned char> bytes, const std::string& source);

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
