#pragma once
// Saving and restoring the application's Bullet bodies for a checkpoint (Shore's own state
// is saved by the terrain, the water and the couplings; docs/checkpoints.md).
//
// As with Shore's objects, the application rebuilds its world the same way (the same bodies
// with the same shapes, masses and settings, added in the same order), then restores the
// evolving state into it:
//
//   shore::CheckpointWriter w(shore::bullet::scalar_bytes());
//   w.add("BODIES", shore::bullet::save_bodies(world));
//   ...
//   shore::bullet::restore_bodies(fresh_world, reader.section("BODIES"), reader.describe("BODIES"));
//
// Saved per rigid body, in the order given (or the world's collision object order), as raw btScalars (a
// checkpoint refuses the other precision): the world and interpolation transforms, the
// linear and angular velocities and their interpolation copies, the activation state and
// deactivation time, the hit fraction; the inverse world inertia follows from the pose.
// Per world: the stepping clock (Bullet's remainder of unstepped time) and the solver's
// random seed. Forces are not saved: stepSimulation clears them, so save between steps.
//
// What Bullet keeps and this cannot restore: its contact manifolds (the contact points and
// their accumulated impulses, which warm-start the next solve) and its broadphase's pair
// order. A world whose bodies touch through Bullet (not through Shore's terrain contact) does
// not continue bit-identically from a restore unless both runs start the continuation
// from no contact points: clear_contact_points() at the save point of the run that goes on
// and after the restore (measured in tests/bullet/test_body_state.cpp).

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>

#include "shore/bullet/config.h"

class btMultiBody;

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

/// sizeof(btScalar): the precision mark a checkpoint holding Bullet state carries.
[[nodiscard]] constexpr std::uint32_t scalar_bytes() noexcept { return sizeof(btScalar); }

/// The evolving state of every rigid body of the world (terrain tiles excluded), and the
/// world's stepping clock.
[[nodiscard]] std::vector<unsigned char> save_bodies(const btDiscreteDynamicsWorld& world);

/// Restores save_bodies' bytes into a world built the same way. FileError naming `source`
/// (the world unchanged) if the bytes are truncated or corrupt, of another version or
/// precision, or the world has another number of rigid bodies or another shape type or
/// mass at some index.
void restore_bodies(btDiscreteDynamicsWorld& world, std::span<const unsigned char> bytes, const std::string& source);

/// The same for `bodies` in the order given (every one in `world`): the order the
/// application added them, which stays put. The world's collision-object order does not:
/// Bullet removes an object by moving the last one into its place, and Shore's couplings
/// add and remove their terrain tiles as bodies move, so two bodies of the same shape and mass
/// could trade states through save_bodies(world) after tiles were removed. Prefer these.
[[nodiscard]] std::vector<unsigned char> save_bodies(const btDiscreteDynamicsWorld& world,
                                                     std::span<btRigidBody* const> bodies);
void restore_bodies(btDiscreteDynamicsWorld& world, std::span<btRigidBody* const> bodies,
                    std::span<const unsigned char> bytes, const std::string& source);

/// Why saved values of a btMultiBody's evolving state cannot be a simulated state ("" if
/// they can), for a game's own multibody checkpoints and recordings. The values' order: base
/// origin, world-to-base quaternion (x, y, z, w), base linear and angular velocity, then per
/// link its joint positions and its joint velocities; `v` holds exactly that many (checked).
/// Refused as restore_bodies refuses a rigid body's: a non-finite value, a base farther
/// than 1e9 m from the origin, a quaternion whose length is off 1 by 1e-3 or more, a base
/// or joint velocity beyond 1e6 m/s or rad/s (Bullet's Featherstone step turns such speeds
/// into NaN).
[[nodiscard]] std::string multibody_state_problem(const btMultiBody& m, std::span<const btScalar> v);

/// Empties every contact manifold of the world (the points and their warm-starting
/// impulses; the pairs stay). Returns the number of points removed.
int clear_contact_points(btDiscreteDynamicsWorld& world);

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
