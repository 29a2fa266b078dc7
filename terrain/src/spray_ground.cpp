#include "spray_ground.h"

#include <algorithm>

namespace shore::terrain {

SprayGround::SprayGround(TileStore& store, const TerrainSettings& s)
    : store_(store),
      n_(store.n()),
      cell_(s.cell),
      area_(s.cell * s.cell),
      origin_x_(s.origin_x),
      origin_y_(s.origin_y),
      soil_depth_(s.material.soil_depth),
      x_min_(s.spray.x_min),
      x_max_(s.spray.x_max),
      y_min_(s.spray.y_min),
      y_max_(s.spray.y_max) {}

double SprayGround::height_looked_up(std::int64_t i, std::int64_t j) const {
  const TileKey key = store_.key_of(i, j);
  const Tile* t = store_.find(key);
  if (t == nullptr) return store_.base_at(i, j);
  last_ = t;
  last_i0_ = key.tx * n_, last_j0_ = key.ty * n_;
  return t->height[store_.local(i, j)];
}

double SprayGround::set(std::int64_t i, std::int64_t j, Tile& t, std::size_t k, double height) {
  const double before = t.height[k];
  if (height == before) return 0.0;
  t.height[k] = height;
  const double moved = height - before;
  t.sinkage[k] -= std::abs(moved);
  const int n = store_.n();
  const int li = static_cast<int>(k % static_cast<std::size_t>(n)),
            lj = static_cast<int>(k / static_cast<std::size_t>(n));
  store_.mark_changed(store_.key_of(i, j), t, li, lj, li, lj);
  return moved * area_;
}

double SprayGround::take(std::int64_t i, std::int64_t j, double depth) {
  if (!(depth > 0.0)) return 0.0;
  Tile& t = store_.tile(store_.key_of(i, j));
  const std::size_t k = store_.local(i, j);
  const double top = t.height[k], bed = t.base[k] - soil_depth_;
  if (!(top > bed)) return 0.0;
  return -set(i, j, t, k, std::max(top - depth, bed));
}

double SprayGround::lay(std::int64_t i, std::int64_t j, double volume) {
  if (!(volume > 0.0)) return 0.0;
  Tile& t = store_.tile(store_.key_of(i, j));
  const std::size_t k = store_.local(i, j);
  return set(i, j, t, k, t.height[k] + volume / area_);
}

}  // namespace shore::terrain
