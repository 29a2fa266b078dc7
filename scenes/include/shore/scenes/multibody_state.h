#pragma once
// A btMultiBody's evolving state as one list of btScalars, in the order the scenes' state
// hash visits it (state.h): base origin, world-to-base quaternion (x, y, z, w), base linear
// and angular velocity, then per link its joint positions and joint velocities. Checkpoints
// (MBODIES) and recordings (each frame's multibody section) save and restore it.

#include <span>
#include <vector>

#include <BulletDynamics/Featherstone/btMultiBody.h>

namespace shore::scenes {

/// The state's values (13 for the base, then each link's position variables and dofs).
[[nodiscard]] std::vector<btScalar> multibody_state(const btMultiBody& m);

/// Sets multibody_state's values (v holds exactly as many, not checked here), with each
/// link's cached rotation and offset from its parent (which Bullet's forward kinematics and
/// its next step read instead of the joint positions), and moves the colliders to where they
/// put them: bit for bit where Bullet's own step put them for the same state (measured on
/// rover; tests/scenes/test_recording.cpp, test_scene_checkpoint.cpp).
void set_multibody_state(btMultiBody& m, std::span<const btScalar> v);

}  // namespace shore::scenes
