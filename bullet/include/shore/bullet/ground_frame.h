#pragma once
// Where the ground lies in the world. The terrain and the water surface have their own
// coordinates: x and y along their grids, z up. A GroundFrame maps those into the Bullet
// world's: ground point p is world point rotation * p + origin. The default is the identity
// (a Z-up world); a Y-up world (gravity along -y: Bullet's examples, Godot, jMonkeyEngine,
// Urho3D) uses GroundFrame::y_up(). Any rotation and origin will do: a tilted or moved
// ground too.
//
// Everything that crosses between the world and the ground goes through the frame: body
// poses, velocities and mass properties in, impulses out, the heightfield tiles placed,
// raycast wheels' rays and pushes, debug drawing. Readouts (terrain_force, water_force)
// are in world coordinates. The identity frame costs nothing: no conversion is made.

#include <string>

#include <LinearMath/btMatrix3x3.h>
#include <LinearMath/btTransform.h>
#include <LinearMath/btVector3.h>

#include "shore/bullet/config.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

struct GroundFrame {
  /// Columns: the ground's x, y and up axes in world coordinates. Must be a proper
  /// rotation (orthonormal, determinant +1, within 1e-5).
  btMatrix3x3 rotation = btMatrix3x3::getIdentity();
  btVector3 origin{0, 0, 0};  ///< m, the ground's origin in world coordinates, finite

  /// Z up: the ground's coordinates are the world's (the default).
  static GroundFrame z_up() { return {}; }
  /// Y up, right-handed: the ground's x is the world's x, its y the world's -z, its up the
  /// world's y (a Z-up world turned by -90 degrees about x). Exact: no rounding in any map.
  static GroundFrame y_up();
  /// The frame a transform gives (its basis and origin).
  static GroundFrame from_transform(const btTransform& t) { return {t.getBasis(), t.getOrigin()}; }

  /// Throws shore::InvalidSetting naming `field` if the rotation is not a finite proper
  /// rotation (scaled, sheared, mirrored, NaN) or the origin is not finite.
  void validate(const std::string& field) const;
  /// True for the identity: nothing to convert.
  [[nodiscard]] bool identity() const;

  [[nodiscard]] btTransform to_world() const { return btTransform(rotation, origin); }
  [[nodiscard]] btTransform to_ground() const { return to_world().inverse(); }
  /// The world's up direction of this ground (its z axis in world coordinates).
  [[nodiscard]] btVector3 up() const { return rotation.getColumn(2); }
  /// Directions (velocities, impulses) between the two.
  [[nodiscard]] btVector3 direction_to_ground(const btVector3& v) const { return v * rotation; }
  [[nodiscard]] btVector3 direction_to_world(const btVector3& v) const { return rotation * v; }
};

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
