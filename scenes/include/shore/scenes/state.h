#pragma once
// The state of a world that the state hash covers: the soils' and water surfaces' own
// hashes, every body's pose and velocities, and rigid ground heights. One hash for every
// scene and reference case: equal hashes mean bit-identical runs (whatever the thread
// count), and tests/scenes pins each scene's.

#include <cstdint>
#include <vector>

#include "shore/bullet/config.h"
#include "shore/scenes/height_grid.h"

class btMultiBody;
class btRigidBody;

namespace shore::terrain {
class Terrain;
}
namespace shore::water {
class Surface;
}

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
class HeightfieldTile;
}
}  // namespace shore::bullet

namespace shore::scenes {

/// How the bodies enter the hash. `standard` is the layout of every new scene and of the
/// reference cases. The others are the layouts the scenes named below hashed when their
/// hashes were pinned; they stay so that those pinned values keep holding. Re-pinning such
/// a scene with `standard` (an intended change of its hash) retires its layout.
enum class HashLayout {
  standard,            ///< per body: origin, basis rows, linear and angular velocity, as doubles
  bullet_scalars,      ///< rigid_drop: the same values as btScalar (the same as standard in double builds)
  positions,           ///< vehicle: per body its origin only
  velocities_by_axis,  ///< pond, beach: per axis origin, linear, angular velocity; then the rotation quaternion
};

/// What a state hash covers, in this order: soils (Terrain::state_hash), water surfaces
/// (Surface::state_hash), bodies (as `layout` says), rigid ground (tile heights as float),
/// multibodies (per multibody, as doubles: base origin, world-to-base rotation quaternion,
/// base linear and angular velocity, then each joint's positions and velocities).
struct SceneState {
  std::vector<const terrain::Terrain*> soils = {};
  std::vector<const water::Surface*> waters = {};
  std::vector<const btRigidBody*> bodies = {};
  std::vector<const bullet::HeightfieldTile*> rigid_grounds = {};
  std::vector<const btMultiBody*> multibodies = {};
  /// Soil heights the scene shows (sampled grids): scanned for non-finite values only.
  std::vector<HeightGrid> soil_heights = {};
  HashLayout layout = HashLayout::standard;
};

/// FNV-1a over the state (shore::StateHash).
[[nodiscard]] std::uint64_t state_hash(const SceneState& state);

/// Non-finite values in the state: body transforms and velocities, water heights, rigid
/// ground heights, multibody poses and joint states, and soil_heights (must be 0).
[[nodiscard]] long non_finite_count(const SceneState& state);

/// Non-finite values in one body's transform and velocities.
[[nodiscard]] long non_finite_count(const btRigidBody& body);

}  // namespace shore::scenes
