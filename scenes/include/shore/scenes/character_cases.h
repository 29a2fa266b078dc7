#pragma once
// A stock character controller on Shore's sand, for the contact stride's speed against its
// error: Bullet's btKinematicCharacterController (a capsule on a btPairCachingGhostObject,
// filtered as Bullet's CharacterDemo filters it) walks straight over hilly sand that earlier
// walkers left a line of footprints in. The capsule is not added to the coupling: it meets
// the soil through Bullet's sweeps and contacts with the tiles, whose triangles the stride
// coarsens. Written once for the tests and the benchmark.

#include <vector>

#include <LinearMath/btVector3.h>

namespace shore::scenes {

struct CharacterWalkCase {
  double cell = 0.02;         ///< m, the soil's columns
  int contact_stride = 1;     ///< TerrainTilesSettings::contact_stride of the coupling
  double seconds = 4.0;       ///< s walked
  double step = 1.0 / 120.0;  ///< s, one world step of one substep
  double speed = 1.3;         ///< m/s, along +x
  double print_depth = 0.03;  ///< m, the footprints' depth (0: none)
};

struct CharacterWalkResult {
  double wall_ms_per_step = 0.0;  ///< ms of stepSimulation per step (the soil does no work)
  std::vector<btVector3> track;   ///< m, the capsule's centre after each step
  /// m, the capsule's lowest point above the soil's column under its centre (negative:
  /// into it; Bullet's sweeps accept the world's allowed CCD penetration): smallest and mean
  /// after the first second.
  double gap_min = 0.0, gap_mean = 0.0;
};

CharacterWalkResult run_character_walk(const CharacterWalkCase& c);

/// The largest distance between two tracks' positions at the same step (over the shorter).
[[nodiscard]] double track_distance(const std::vector<btVector3>& a, const std::vector<btVector3>& b);

}  // namespace shore::scenes
