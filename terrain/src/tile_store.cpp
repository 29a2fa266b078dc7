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
  if (!slot) {
    slot = std::make_unique<Tile>(n_);
    // Untouched ground is the base source; sample it once, when the tile is created.
    for (int lj = 0; lj < n_; ++lj)
      for (int li = 0; li < n_; ++li) {
        const double b = base_at(key.tx * n_ + li, key.ty * n_ + lj);
        const std::size_t k = static_cast<std::size_t>(lj) * n_ + li;
        slot->base[k] = b;
        slot->height[k] = b;
      }
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
  log_change(key, t, li0, lj0, li1, lj1);
}

void TileStore::log_change(TileKey key, Tile& t, int li0, int lj0, int li1, int lj1) {
  if (t.changed_at == generation_) {  // this generation's entry for the tile: widen it
    ChangeEntry& e = log_[t.log_entry];
    e.i0 = std::min(e.i0, li0), e.j0 = std::min(e.j0, lj0);
    e.i1 = std::max(e.i1, li1), e.j1 = std::max(e.j1, lj1);
    return;
  }
  t.changed_at = generation_;
  t.log_entry = log_.size();
  log_.push_back({generation_, key, li0, lj0, li1, lj1});
}

void TileStore::advance_generation() {
  ++generation_;
  // The log keeps the recent generations only: past a few entries per tile the oldest half
  // goes, and an observer older than what is left gets whole tiles (still every change).
  const std::size_t limit = std::max<std::size_t>(1024, 4 * tiles_.size());
  if (log_.size() <= limit) return;
  const std::uint64_t cut = log_[log_.size() / 2].generation;
  const auto keep = std::upper_bound(log_.begin(), log_.end(), cut,
                                     [](std::uint64_t g, const ChangeEntry& e) { return g < e.generation; });
  log_.erase(log_.begin(), keep);
  log_floor_ = cut;
  // Entries of the current generation cannot be dropped (it has none yet), so the tiles'
  // log_entry indices are only needed for it and need no update.
}

ColumnRect TileStore::whole_tile(TileKey key) const { return {key.tx * n_, key.ty * n_, n_, n_}; }

std::vector<ColumnRect> TileStore::changed_since(std::uint64_t g) const {
  std::vector<ColumnRect> rects;
  if (g < log_floor_) {  // older than the log: every tile changed since, whole
    for (const TileKey& key : sorted_keys())
      if (find(key)->changed_at > g) rects.push_back(whole_tile(key));
    return rects;
  }
  const auto first = std::upper_bound(log_.begin(), log_.end(), g,
                                      [](std::uint64_t gen, const ChangeEntry& e) { return gen < e.generation; });
  std::vector<ChangeEntry> entries(first, log_.end());
  std::sort(entries.begin(), entries.end(), [](const ChangeEntry& a, const ChangeEntry& b) { return a.key < b.key; });
  for (std::size_t k = 0; k < entries.size();) {
    ChangeEntry box = entries[k];
    for (++k; k < entries.size() && entries[k].key == box.key; ++k) {
      box.i0 = std::min(box.i0, entries[k].i0), box.j0 = std::min(box.j0, entries[k].j0);
      box.i1 = std::max(box.i1, entries[k].i1), box.j1 = std::max(box.j1, entries[k].j1);
    }
    rects.push_back({box.key.tx * n_ + box.i0, box.key.ty * n_ + box.j0, box.i1 - box.i0 + 1, box.j1 - box.j0 + 1});
  }
  return rects;
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
  if (!tiles_.emplace(key, std::move(t)).second) return false;
  mark_changed(key, added, 0, 0, n_ - 1, n_ - 1);
  return true;
}

std::size_t TileStore::bytes() const {
  constexpr std::size_t kNodeBytes = sizeof(TileKey) + 2 * sizeof(void*);  // hash node: key, owner, next
  std::size_t total = tiles_.bucket_count() * sizeof(void*) + capacity_bytes(dirty_keys_, log_);
  for (const auto& entry : tiles_) total += kNodeBytes + entry.second->bytes();
  return total;
}

}  // namespace shore::terrain
