#pragma once
// Plain rigid Bullet ground: one HeightfieldTile in a World. The ground of scenes without
// soil and the "plain rigid Bullet heightfield" baseline of the benchmarks.

#include <functional>
#include <memory>

#include "shore/bullet/heightfield_tile.h"
#include "shore/scenes/height_grid.h"
#include "shore/scenes/world.h"

namespace shore::scenes {

class RigidGround {
 public:
  /// Adds the tile to world; height(x, y) gives the initial height (m) of each vertex.
  RigidGround(World& world, const bullet::HeightfieldTileSettings& tile,
              const std::function<double(double, double)>& height);
  ~RigidGround();
  RigidGround(const RigidGround&) = delete;
  RigidGround& operator=(const RigidGround&) = delete;

  [[nodiscard]] const bullet::HeightfieldTile& tile() const noexcept { return *tile_; }
  /// The tile's heights as a HeightGrid.
  [[nodiscard]] HeightGrid grid() const;
  /// Height under world (x, y) on Bullet's triangles (the diagonal split it uses).
  [[nodiscard]] double height_at(double x, double y) const;

 private:
  World& world_;
  std::unique_ptr<bullet::HeightfieldTile> tile_;
};

}  // namespace shore::scenes
