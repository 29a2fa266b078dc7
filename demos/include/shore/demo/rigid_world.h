#pragma once
// A plain Bullet world on one rigid HeightfieldTile: the ground every scene without soil
// uses, and the "plain rigid Bullet heightfield" baseline of the benchmarks.

#include <functional>
#include <memory>
#include <vector>

#include <btBulletDynamicsCommon.h>

#include "shore/bullet/heightfield_tile.h"
#include "shore/core/hash.h"
#include "shore/demo/height_grid.h"

namespace shore::demo {

class RigidWorld {
 public:
  /// ground(x, y) gives the initial height (m) of each tile vertex.
  RigidWorld(const bullet::HeightfieldTileSettings& tile, const std::function<double(double, double)>& ground,
             double gravity = 9.81);
  RigidWorld(const RigidWorld&) = delete;
  RigidWorld& operator=(const RigidWorld&) = delete;
  ~RigidWorld();

  /// Adds a dynamic box (half extents in m, mass in kg) at pose; returns it (owned here).
  btRigidBody& add_box(const btVector3& half_extents, double mass, const btTransform& pose);
  /// Adds a dynamic cylinder with its axis along the body's y (a wheel rolling along x).
  btRigidBody& add_cylinder(double radius, double half_width, double mass, const btTransform& pose);

  /// One fixed substep of h seconds (stepSimulation(h, 1, h)).
  void step(double h);

  /// FNV-1a over every body's transform and velocities and the tile heights.
  [[nodiscard]] std::uint64_t state_hash() const;
  /// Non-finite values among body states and tile heights.
  [[nodiscard]] long nan_count() const;

  /// Tile heights as a HeightGrid.
  [[nodiscard]] HeightGrid ground_grid() const;
  struct Envelopes {
    HeightGrid top;     ///< highest body point over each column (NaN: no body)
    HeightGrid bottom;  ///< lowest body point over each column (NaN: no body)
  };
  /// Upper and lower surfaces of the bodies over the tile's columns, by casting vertical
  /// rays against each body: for pictures.
  [[nodiscard]] Envelopes body_envelopes() const;
  /// Tile height under world (x, y) on Bullet's triangles (the diagonal split it uses).
  [[nodiscard]] double ground_height(double x, double y) const;

  [[nodiscard]] btDiscreteDynamicsWorld& world() noexcept { return *world_; }
  [[nodiscard]] bullet::HeightfieldTile& tile() noexcept { return *tile_; }
  [[nodiscard]] const std::vector<btRigidBody*>& bodies() const noexcept { return body_list_; }

 private:
  btRigidBody& add_body(std::unique_ptr<btCollisionShape> shape, double mass, const btTransform& pose);

  std::unique_ptr<btDefaultCollisionConfiguration> config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btDbvtBroadphase> broadphase_;
  std::unique_ptr<btSequentialImpulseConstraintSolver> solver_;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;
  std::unique_ptr<bullet::HeightfieldTile> tile_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btMotionState>> motions_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
  std::vector<btRigidBody*> body_list_;
};

/// Lowest point (z) of a box body's corners.
double lowest_corner_z(const btRigidBody& box, const btVector3& half_extents);

}  // namespace shore::demo
