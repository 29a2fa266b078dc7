#include "region.h"

#include <algorithm>

#include <cstring>

#include "capacity_bytes.h"

namespace shore::terrain {

void Region::prepare(const GridRect& with_halo, Team* rows_team) {
  si0 = with_halo.i0, sj0 = with_halo.j0, w = with_halo.nx, h = with_halo.ny;
  team = rows_team;
}

void Region::gather(TileStore& store, const BedrockDepth& depth, bool with_materials, bool with_layers) {
  // Sized, not cleared: gather writes every column.
  for (auto* v : {&ht, &sink, &bed}) v->resize(size());
  if (with_materials)
    mat.resize(size());
  else
    mat.clear();
  if (with_layers) {
    layer.boundary.resize(size());
    layer.lower.resize(size());
  } else {
    layer.boundary.clear();
    layer.lower.clear();
  }
  store.for_each_run_creating({si0, sj0, w, h}, [&](Tile& t, const TileRun& run) {
    const std::size_t src = run.local;
    const std::size_t dst = at(run.x, run.y);
    std::memcpy(&ht[dst], &t.height[src], sizeof(double) * run.count);
    std::memcpy(&sink[dst], &t.sinkage[src], sizeof(double) * run.count);
    if (depth.uniform()) {
      const double soil_depth = depth.at(0);
      for (int k = 0; k < run.count; ++k) bed[dst + k] = t.base[src + k] - soil_depth;
    } else {
      for (int k = 0; k < run.count; ++k) bed[dst + k] = t.base[src + k] - depth.at(t.material, src + k);
    }
    if (with_layers) {
      if (t.layered()) {
        std::memcpy(&layer.boundary[dst], &t.layer_boundary[src], sizeof(double) * run.count);
        std::memcpy(&layer.lower[dst], &t.layer_lower[src], static_cast<std::size_t>(run.count));
      } else {
        std::fill_n(&layer.boundary[dst], run.count, kNoLayer);
        std::memset(&layer.lower[dst], 0, static_cast<std::size_t>(run.count));
      }
    }
    if (!with_materials) return;
    if (t.material.empty())
      std::memset(&mat[dst], 0, static_cast<std::size_t>(run.count));
    else
      std::memcpy(&mat[dst], &t.material[src], static_cast<std::size_t>(run.count));
  });
  relayered.clear();
}

void Region::scatter(TileStore& store) {
  // The tiles still hold the heights gathered (only scatter writes them during a step), so
  // what changed is read against them, and only the changed span of a run is written back.
  store.for_each_run_creating({si0, sj0, w, h}, [&](Tile& t, const TileRun& run) {
    const std::size_t src = at(run.x, run.y);
    const std::size_t dst = run.local;
    int first = -1, last = -1;
    for (int k = 0; k < run.count; ++k)
      if (ht[src + k] != t.height[dst + k]) {
        if (first < 0) first = k;
        last = k;
      }
    std::memcpy(&t.sinkage[dst], &sink[src], sizeof(double) * run.count);
    if (first < 0) return;
    std::copy(&ht[src + first], &ht[src + last] + 1, &t.height[dst + first]);
    store.mark_changed(run.key, t, GridRect::spanning(run.li + first, run.lj, run.li + last, run.lj));
  });
  if (!relayered.empty()) scatter_relayered(store);
}

void Region::scatter_relayered(TileStore& store) {
  bool any_layer = false;
  touched_.clear();
  Touched* at = nullptr;  // the tile of the column before
  const std::int64_t n = store.n();
  for (const Relayered& c : relayered) {
    const std::int64_t i = si0 + static_cast<std::int64_t>(c.k % static_cast<std::size_t>(w));
    const std::int64_t j = sj0 + static_cast<std::int64_t>(c.k / static_cast<std::size_t>(w));
    // Row by row: most columns lie in the tile of the one before (tested by its bounds),
    // the rest in one this scatter has already looked up (a region spans a few tiles), so
    // the store's table is asked once per tile.
    if (at == nullptr || i < at->i0 || i >= at->i0 + n || j < at->j0 || j >= at->j0 + n) {
      const TileKey key = store.key_of(i, j);
      const std::int64_t i0 = key.tx * n, j0 = key.ty * n;
      const auto seen =
          std::find_if(touched_.begin(), touched_.end(), [&](const Touched& u) { return u.i0 == i0 && u.j0 == j0; });
      if (seen != touched_.end()) {
        at = &*seen;
      } else {
        Tile& t = store.tile(key);
        store.mark_painted(t);
        at = &touched_.emplace_back(Touched{&t, i0, j0});
      }
    }
    Tile* t = at->tile;
    const auto local = static_cast<std::size_t>((j - at->j0) * n + (i - at->i0));
    // Only a nonzero index turned 0 can leave the map all 0, only a layered column turned
    // unlayered the tile unlayered (a tile's arrays are kept normalised, as painting keeps them).
    if (t->material.empty() && c.index != 0) t->material.assign(t->height.size(), 0);
    if (!t->material.empty()) {
      if (c.index == 0 && t->material[local] != 0 && !at->unpainted) {
        at->unpainted = true;
        at->unpainted_at = local;
      }
      t->material[local] = c.index;
    }
    if (c.layer.layered() && !t->layered()) {
      t->layer_boundary.assign(t->height.size(), kNoLayer);
      t->layer_lower.assign(t->height.size(), 0);
    }
    if (t->layered()) {
      if (!c.layer.layered() && t->layer_boundary[local] != kNoLayer && !at->unlayered) {
        at->unlayered = true;
        at->unlayered_at = local;
      }
      t->layer_boundary[local] = c.layer.boundary;
      t->layer_lower[local] = c.layer.layered() ? c.layer.lower : std::uint8_t{0};
    }
    any_layer = any_layer || c.layer.layered();
  }
  // A tile's map and layers are dropped once all 0 / unlayered, as painting does: once per
  // tile, after its columns are written (each check reads the whole tile), and only where
  // a write could have made it so.
  for (const Touched& u : touched_) {
    if (u.unpainted) u.tile->normalize_material(u.unpainted_at);
    if (u.unlayered) u.tile->normalize_layers(u.unlayered_at);
  }
  if (any_layer) store.mark_layered();
}

std::size_t Region::bytes() const {
  return capacity_bytes(ht, ht_pressed, sink, bed, mat, layer.boundary, layer.lower, upper, relayered, touched_);
}

}  // namespace shore::terrain
