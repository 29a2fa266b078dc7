#include "spray_ground.h"

#include <algorithm>
#include <limits>

namespace shore::terrain {

SprayGround::SprayGround(TileStore& store, const TerrainSettings& s, std::span<const Material> palette,
                         UntiledTops* untiled, TiledTops* tiled)
    : store_(store),
      index_(store),
      tops_(store, untiled, tiled),
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

SprayGround::ChangedTile& SprayGround::changed_tile_looked_up(const TileKey& key, ChangedTile& c) {
  // A tile kept in another slot before: store_.tile() finds it and sets its last use to
  // this step's tick again (the tick does not move during a spray step, nor is a tile
  // released); its box starts empty again, which only costs a call.
  c = ChangedTile{key, &store_.tile(key)};
  return c;
}

void SprayGround::mark_new(ChangedTile& c, int li, int lj) {
  store_.mark_changed(c.key, *c.tile, {li, lj, 1, 1});
  if (c.i1 < c.i0) {
    c.i0 = c.i1 = li, c.j0 = c.j1 = lj;
    return;
  }
  c.i0 = std::min(c.i0, li), c.i1 = std::max(c.i1, li);
  c.j0 = std::min(c.j0, lj), c.j1 = std::max(c.j1, lj);
}

double SprayGround::take(std::int64_t i, std::int64_t j, double depth) {
  if (!(depth > 0.0)) return 0.0;
  ChangedTile& c = changed_tile(index_.key_of(i, j));
  const Tile& t = *c.tile;
  const std::size_t k = index_.local(i, j);
  const double top = t.height[k], bed = t.base[k] - (depth_.uniform() ? soil_depth_ : depth_.at(t.material, k));
  if (!(top > bed)) return 0.0;
  return -set(i, j, c, k, std::max(top - depth, bed));
}

}  // namespace shore::terrain
