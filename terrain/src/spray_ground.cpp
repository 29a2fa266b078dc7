#include "spray_ground.h"

#include <algorithm>
#include <limits>

namespace shore::terrain {

SprayGround::SprayGround(TileStore& store, const TerrainSettings& s, std::span<const Material> palette,
                         UntiledTops* untiled)
    : store_(store),
      index_(store),
      tops_(store, untiled),
      n_(store.n()),
      cell_(s.cell),
      inverse_cell_(1.0 / s.cell),
      area_(s.cell * s.cell),
      origin_x_(s.origin_x),
      origin_y_(s.origin_y),
      soil_depth_(s.material.soil_depth),
      depth_(palette, s.material.soil_depth),
      x_min_(s.spray.x_min),
      x_max_(s.spray.x_max),
      y_min_(s.spray.y_min),
      y_max_(s.spray.y_max) {}

void SprayGround::cover(double x0, double y0, double x1, double y1) {
  std::int64_t c[4];
  if (columns_around(x0, y0, x1, y1, 3, c)) tops_.cover(c[0], c[1], c[2], c[3]);
}

double SprayGround::height_looked_up(std::int64_t i, std::int64_t j) const {
  const TileKey key = index_.key_of(i, j);
  SeenTile& seen = seen_[seen_slot(key)];
  const Tile* t = seen.tile != nullptr && seen.tx == key.tx && seen.ty == key.ty ? seen.tile : store_.find(key);
  if (t == nullptr) return store_.base_at(i, j);
  seen = {key.tx, key.ty, t};
  last_ = t;
  last_i0_ = key.tx * n_, last_j0_ = key.ty * n_;
  return t->height[static_cast<std::size_t>((j - last_j0_) * n_ + (i - last_i0_))];
}

Tile& SprayGround::changed_tile(const TileKey& key) {
  // The same tile as the last: store_.tile() would find it and set its last use to this
  // step's tick again (the tick does not move during a spray step, nor is a tile released).
  if (changed_ != nullptr && changed_key_ == key) return *changed_;
  changed_ = &store_.tile(key);
  changed_key_ = key;
  return *changed_;
}

double SprayGround::set(std::int64_t i, std::int64_t j, const TileKey& key, Tile& t, std::size_t k, double height) {
  const double before = t.height[k];
  if (height == before) return 0.0;
  t.height[k] = height;
  const double moved = height - before;
  t.sinkage[k] -= std::abs(moved);
  const int li = static_cast<int>(i - key.tx * n_), lj = static_cast<int>(j - key.ty * n_);
  if (moved > 0.0) tops_.raised(i, j, height);
  store_.mark_changed(key, t, {li, lj, 1, 1});
  return moved * area_;
}

double SprayGround::take(std::int64_t i, std::int64_t j, double depth) {
  if (!(depth > 0.0)) return 0.0;
  const TileKey key = index_.key_of(i, j);
  Tile& t = changed_tile(key);
  const std::size_t k = index_.local(i, j);
  const double top = t.height[k], bed = t.base[k] - (depth_.uniform() ? soil_depth_ : depth_.at(t.material, k));
  if (!(top > bed)) return 0.0;
  return -set(i, j, key, t, k, std::max(top - depth, bed));
}

double SprayGround::lay(std::int64_t i, std::int64_t j, double volume) {
  if (!(volume > 0.0)) return 0.0;
  const TileKey key = index_.key_of(i, j);
  Tile& t = changed_tile(key);
  const std::size_t k = index_.local(i, j);
  return set(i, j, key, t, k, t.height[k] + volume / area_);
}

}  // namespace shore::terrain
