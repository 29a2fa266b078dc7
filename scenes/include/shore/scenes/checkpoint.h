#pragma once
// A checkpoint of a whole scene (docs/checkpoints.md): everything its contents() holds
// (soils, water surfaces, their couplings), every Bullet body and multibody of its world, and its
// script's clock. Restore into the same scene created with the same options: the
// continued run is bit-identical (state hash) to the uninterrupted one. The scene's
// measurements over time (observe) are not saved: they start again from the restore.
//
// Sections: TERRAIN, TERRAIN1, ... (Terrain::save_bytes), TERRCP, TERRCP1, ... (their
// TerrainCoupling::save_state), WATER, WATER1, ... (Surface::save_state), WATERCP, ...
// (WaterCoupling::save_state), BODIES (bullet::save_bodies), MBODIES (a Featherstone
// world's multibodies, if it has any: per multibody its base pose and velocities and its
// joints' positions and rates as btScalars), VEHICLE, VEHICLE1, ... (its raycast vehicles'
// wheels: bullet::save_vehicle), SCENE (the clock).

#include <span>
#include <string>
#include <vector>

#include "shore/core/checkpoint_file.h"
#include "shore/scenes/scene.h"

namespace shore::scenes {

/// The checkpoint of the scene as it is now. InvalidSetting if the scene shows no world
/// (contents().world is null).
[[nodiscard]] CheckpointWriter save_checkpoint(Scene& scene);

/// Restores a checkpoint into a scene created with the same options. FileError naming the
/// checkpoint and the section for a section missing or not matching the scene.
void restore_checkpoint(Scene& scene, const CheckpointReader& checkpoint);

}  // namespace shore::scenes
