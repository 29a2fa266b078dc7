#include "tile_store.h"

#include "capacity_bytes.h"

namespace shore::terrain {

Tile::Tile(int n) : height(static_cast<std::size_t>(n) * n), sinkage(height.size(), 0.0), base(height.size()) {}

void Tile::mark_dirty(int li0, int lj0, int li1, int lj1) {
  if (!dirty) {
    dirty = true;
    di0 = li0, dj0 = lj0, di1 = li1, dj1 = lj1;
    return;
  }
  di0 = std::min(di0, li0), dj0 = std::min(dj0, lj0);
  di1 = std::max(di1, li1), dj1 = std::max(dj1, lj1);
}

bool Tile::holds_only_base() const {
  bool same = true;  // no early exit: a branch-free pass over the arrays
  for (std::size_t k = 0; k < height.size(); ++k) same &= height[k] == base[k] && sinkage[k] == 0.0;
  return same;
}

std::size_t Tile::bytes() const { return sizeof(Tile) + capacity_bytes(height, sinkage, base); }

TileStore::TileStore(const TerrainSettings& s)
    : n_(s.tile_columns),
      cell_(s.cell),
      origin_x_(s.origin_x),
      origin_y_(s.origin_y),
      base_height_(s.base_height),
      base_(s.base) {}

double TileStore::base_at(std::int64_t i, std::int64_t j) const {
  if (!base_) return base_height_;
  return base_->height(origin_x_ + static_cast<double>(i) * cell_, origin_y_ + static_cast<double>(j) * cell_);
}

const Tile* TileStore::find(TileKey key) const {
  const auto it = tiles_.find(key);
  return it == tiles_.end() ? nullptr : it->second.get();
}

Tile& TileStore::tile(TileKey key) {
  auto& slot = tiles_[key];
  if (slot) {
    slot->last_used = clock_;
  } else {
    slot = std::make_unique<Tile>(n_);
    // Untouched ground is the base source; sample it once, when the tile is created.
    for (int lj = 0; lj < n_; ++lj)
      for (int li = 0; li < n_; ++li) {
        const double b = base_at(key.tx * n_ + li, key.ty * n_ + lj);
        const std::size_t k = static_cast<std::size_t>(lj) * n_ + li;
        slot->base[k] = b;
        slot->height[k] = b;
      }
    slot->last_used = clock_;
  }
  return *slot;
}

std::vector<TileKey> TileStore::sorted_keys() const {
  std::vector<TileKey> keys;
  keys.reserve(tiles_.size());
  for (const auto& [key, tile] : tiles_) keys.push_back(key);
  std::sort(keys.begin(), keys.end());
  return keys;
}

void TileStore::read(const ColumnRect& r, std::span<double> out, bool base) const {
  for_each_run(r, [&](const Tile* t, const TileRun& run) {
    double* dst = out.data() + static_cast<std::size_t>(run.y) * static_cast<std::size_t>(r.nx) + run.x;
    if (t) {
      const std::vector<double>& field = base ? t->base : t->height;
      std::copy_n(field.data() + run.local, run.count, dst);
    } else {
      const std::int64_t i = r.i0 + run.x, j = r.j0 + run.y;
      for (int c = 0; c < run.count; ++c) dst[c] = base_at(i + c, j);
    }
  });
}

void TileStore::mark_changed(TileKey key, Tile& t, int li0, int lj0, int li1, int lj1) {
  if (!t.dirty) dirty_keys_.push_back(key);
  t.mark_dirty(li0, lj0, li1, lj1);
}

std::vector<ColumnRect> TileStore::take_changed() {
  std::sort(dirty_keys_.begin(), dirty_keys_.end());
  std::vector<ColumnRect> rects;
  rects.reserve(dirty_keys_.size());
  for (const TileKey& key : dirty_keys_) {
    const auto it = tiles_.find(key);
    if (it == tiles_.end() || !it->second->dirty) continue;
    Tile& t = *it->second;
    rects.push_back({key.tx * n_ + t.di0, key.ty * n_ + t.dj0, t.di1 - t.di0 + 1, t.dj1 - t.dj0 + 1});
    t.dirty = false;
  }
  dirty_keys_.clear();
  return rects;
}

bool TileStore::adopt(TileKey key, std::unique_ptr<Tile> t) {
  Tile& added = *t;
  added.from_source = false;
  added.last_used = clock_;
  if (!tiles_.emplace(key, std::move(t)).second) return false;
  mark_changed(key, added, 0, 0, n_ - 1, n_ - 1);
  return true;
}

bool TileStore::releasable(TileKey key, Tile& t, std::int64_t idle_steps) const {
  if (t.dirty || clock_ - t.last_used < idle_steps || t.kept_at == t.last_used) return false;
  bool base_matches = t.from_source;
  if (!base_matches) {  // a loaded tile: its base may come from another source than this store's
    base_matches = true;
    for (int lj = 0; lj < n_; ++lj)
      for (int li = 0; li < n_; ++li)
        base_matches &= t.base[static_cast<std::size_t>(lj) * n_ + li] == base_at(key.tx * n_ + li, key.ty * n_ + lj);
  }
  if (base_matches && t.holds_only_base()) return true;
  t.kept_at = t.last_used;  // unchanged until a step uses it again: no need to compare again
  return false;
}

std::size_t TileStore::release_idle(std::int64_t idle_steps) {
  if (clock_ % kReleaseScanTicks != 0) return 0;
  std::size_t released = 0;
  // Each tile's fate depends on that tile alone, so the map's order does not matter.
  for (auto it = tiles_.begin(); it != tiles_.end();) {
    if (releasable(it->first, *it->second, idle_steps)) {
      it = tiles_.erase(it);
      ++released;
    } else {
      ++it;
    }
  }
  return released;
}

std::size_t TileStore::bytes() const {
  constexpr std::size_t kNodeBytes = sizeof(TileKey) + 2 * sizeof(void*);  // hash node: key, owner, next
  std::size_t total = tiles_.bucket_count() * sizeof(void*) + capacity_bytes(dirty_keys_);
  for (const auto& entry : tiles_) total += kNodeBytes + entry.second->bytes();
  return total;
}

}  // namespace shore::terrain
