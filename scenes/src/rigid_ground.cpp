#include "shore/scenes/rigid_ground.h"

#include <algorithm>

namespace shore::scenes {

RigidGround::RigidGround(World& world, const bullet::HeightfieldTileSettings& tile,
                         const std::function<double(double, double)>& height)
    : world_(world), tile_(std::make_unique<bullet::HeightfieldTile>(tile)) {
  const auto& s = tile_->settings();
  for (int j = 0; j < s.columns; ++j)
    for (int i = 0; i < s.columns; ++i)
      tile_->set_height(i, j, height(s.origin_x + i * s.cell, s.origin_y + j * s.cell));
  world_.world().addCollisionObject(tile_->object());
}

RigidGround::~RigidGround() { world_.world().removeCollisionObject(tile_->object()); }

HeightGrid RigidGround::grid() const {
  const auto& s = tile_->settings();
  HeightGrid g(s.columns, s.columns, s.cell, s.origin_x, s.origin_y);
  for (int j = 0; j < s.columns; ++j)
    for (int i = 0; i < s.columns; ++i) g.at(i, j) = tile_->height(i, j);
  return g;
}

double RigidGround::height_at(double x, double y) const {
  const auto& s = tile_->settings();
  const double fi = std::clamp((x - s.origin_x) / s.cell, 0.0, s.columns - 1.0);
  const double fj = std::clamp((y - s.origin_y) / s.cell, 0.0, s.columns - 1.0);
  const int i = std::min(static_cast<int>(fi), s.columns - 2);
  const int j = std::min(static_cast<int>(fj), s.columns - 2);
  const double u = fi - i, v = fj - j;
  // Bullet 3.24 splits each cell along the (i+1, j)-(i, j+1) diagonal unless told otherwise.
  const double h00 = tile_->height(i, j), h10 = tile_->height(i + 1, j);
  const double h01 = tile_->height(i, j + 1), h11 = tile_->height(i + 1, j + 1);
  if (u + v <= 1.0) return h00 + u * (h10 - h00) + v * (h01 - h00);
  return h11 + (1.0 - u) * (h01 - h11) + (1.0 - v) * (h10 - h11);
}

}  // namespace shore::scenes
