#pragma once
// One square patch of ground as a Bullet btHeightfieldTerrainShape, editable in place.
//
// Bullet 3.24 facts this class hides (measured):
// - the height data is referenced, not copied: edits to the buffer are seen at once;
// - min/max heights only set the AABB, and the shape's local origin is the AABB centre,
//   so the object sits at z = (min + max) / 2 for world heights to equal buffer heights;
// - heights outside [min, max] are clamped: set_height() clamps and reports it;
// - with Z up the triangle winding must be flipped for normals to point up;
// - the accelerator (buildAccelerator) is stale after edits: it is never built here;
// - a box sliding over a flat heightfield catches on the triangles' internal edges (contact
//   normals from an edge, not the face) and loses about half its speed on a frictionless
//   15 degree slope, at 1 cm or 10 cm cells alike; Bullet's internal-edge info
//   (btGenerateInternalEdgeInfo + btAdjustInternalEdgeContacts) removes it, but the info
//   is computed from the heights, so it suits ground that no longer changes
//   (smooth_internal_edges).
// Column (i, j) of the tile is at world (origin_x + i * cell, origin_y + j * cell).

#include <memory>
#include <span>
#include <vector>

#include <LinearMath/btScalar.h>

#include <BulletCollision/CollisionDispatch/btCollisionObject.h>
#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>
#include <BulletCollision/CollisionShapes/btTriangleInfoMap.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include "shore/bullet/config.h"

class btManifoldPoint;
struct btCollisionObjectWrapper;

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

struct HeightfieldTileSettings {
  int columns = 65;             ///< vertices per side, >= 2
  double cell = 0.01;           ///< m, spacing of vertices, > 0
  double origin_x = 0.0;        ///< m, world x of vertex (0, 0)
  double origin_y = 0.0;        ///< m, world y of vertex (0, 0)
  double min_height = -1.0;     ///< m, lowest height the tile can hold (< max_height)
  double max_height = 1.0;      ///< m, highest height the tile can hold
  double initial_height = 0.0;  ///< m, in [min_height, max_height]
  double friction = 0.6;        ///< Coulomb friction, >= 0
  /// Vertices per triangle edge in Bullet's convex contacts and sweeps (the shape's
  /// processAllTriangles): 1, every vertex; k > 1, one triangle pair per k x k cells, their
  /// corners every k-th vertex (the heights there, not a fit), so a capsule or box meets
  /// k^2 times fewer triangles. Ray tests (btRaycastVehicle, picking) always see every
  /// vertex. >= 1 and dividing columns - 1, so neighbouring tiles share their coarse edges.
  int contact_stride = 1;

  void validate() const;
};

class HeightfieldTile {
 public:
  explicit HeightfieldTile(const HeightfieldTileSettings& settings);
  HeightfieldTile(const HeightfieldTile&) = delete;
  HeightfieldTile& operator=(const HeightfieldTile&) = delete;

  /// Sets the world height of vertex (i, j), clamped to [min, max]. Returns false if it
  /// had to clamp.
  bool set_height(int i, int j, double h);
  [[nodiscard]] double height(int i, int j) const;

  /// What set_row did.
  struct RowWrite {
    int clamped = 0;      ///< vertices clamped to [min, max]
    int first_held = -1;  ///< first index into h held back by max_rise (-1: none)
    int last_held = -1;   ///< last such index
  };
  /// Sets vertices (i0 + k, j), k < h.size(), to h[k] (clamped to [min, max]), except that
  /// none rises more than max_rise above its current height.
  RowWrite set_row(int i0, int j, std::span<const double> h, double max_rise);
  [[nodiscard]] int columns() const noexcept { return settings_.columns; }
  [[nodiscard]] const HeightfieldTileSettings& settings() const noexcept { return settings_; }

  /// The tile's object, owned by the tile: a static btRigidBody (mass 0), so that queries
  /// accepting only rigid bodies (btDefaultVehicleRaycaster's ray casts) find the ground.
  /// Add it with btCollisionWorld::addCollisionObject: as a static object of a dynamics
  /// world it takes part in collisions only, exactly as a plain collision object does.
  [[nodiscard]] btRigidBody* object() noexcept { return object_.get(); }
  [[nodiscard]] btHeightfieldTerrainShape* shape() noexcept { return shape_.get(); }

  /// Computes Bullet's internal-edge info from the current heights and has contacts with
  /// the tile corrected by it (adjust_internal_edge_contact), so bodies slide over the
  /// tile's flat parts as over one face. For ground that no longer changes (rigid
  /// material): after a height edit the info is stale. Installs terrain_contact_added as
  /// Bullet's global gContactAddedCallback if it is unset; an application with its own
  /// callback calls terrain_contact_added (or adjust_internal_edge_contact) from it.
  void smooth_internal_edges();

  /// Friction per vertex, row-major (index j * columns + i, columns^2 values, each >= 0),
  /// for the bodies Bullet collides with the tile (a painted material map): a contact takes
  /// the friction of the vertex nearest its point on the tile, combined with the body's as
  /// Bullet combines by default (the product, clamped to 10), in terrain_contact_added.
  /// Empty: the object's one friction everywhere, and no per-contact work. Installs
  /// terrain_contact_added as Bullet's global gContactAddedCallback if it is unset (or is
  /// adjust_internal_edge_contact); an application with its own callback calls
  /// terrain_contact_added from it. Throws InvalidSetting on a wrong size or a bad value.
  void set_vertex_friction(std::vector<btScalar> friction);
  [[nodiscard]] bool has_vertex_friction() const noexcept { return !vertex_friction_.empty(); }
  /// The friction of the vertex nearest a point given in the tile object's own frame (the
  /// object's one friction without a vertex friction).
  [[nodiscard]] btScalar friction_near(const btVector3& local) const;

 private:
  /// Sets or clears the object's custom-material flag: on while the tile has internal-edge
  /// info or a vertex friction.
  void update_callback_flag();
  HeightfieldTileSettings settings_;
  std::vector<float> heights_;  // row-major, index j * columns + i
  std::unique_ptr<btHeightfieldTerrainShape> shape_;
  std::unique_ptr<btRigidBody> object_;
  std::unique_ptr<btTriangleInfoMap> edge_info_;
  std::vector<btScalar> vertex_friction_;  ///< empty: the object's friction everywhere
};

/// Bullet's ContactAddedCallback signature: corrects a contact with a smoothed tile (either
/// object) by its internal-edge info; does nothing for other pairs. Always returns false.
bool adjust_internal_edge_contact(btManifoldPoint& cp, const btCollisionObjectWrapper* a, int part_a, int index_a,
                                  const btCollisionObjectWrapper* b, int part_b, int index_b);

/// Bullet's ContactAddedCallback signature, what Shore installs: a contact with a tile
/// (either object) is corrected by the tile's internal-edge info if it has any
/// (adjust_internal_edge_contact), then given the friction of the tile's vertex nearest the
/// contact if the tile has a vertex friction (set_vertex_friction). Does nothing for other
/// pairs. Always returns false.
bool terrain_contact_added(btManifoldPoint& cp, const btCollisionObjectWrapper* a, int part_a, int index_a,
                           const btCollisionObjectWrapper* b, int part_b, int index_b);

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
