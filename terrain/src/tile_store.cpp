#include "tile_store.h"

#include "capacity_bytes.h"

#include <algorithm>
#include <cstring>

namespace shore::terrain {

Tile::Tile(int n) : height(static_cast<std::size_t>(n) * n), sinkage(height.size(), 0.0), base(height.size()) {}

bool Tile::holds_only_base() const {
  if (!material.empty() || layered()) return false;  // painted: differs from the default map
  bool same = true;                                  // no early exit: a branch-free pass over the arrays
  for (std::size_t k = 0; k < height.size(); ++k) same &= height[k] == base[k] && sinkage[k] == 0.0;
  return same;
}

namespace {

// Whether every index of [from, to) is 0, eight at a time.
bool all_zero(const std::uint8_t* from, const std::uint8_t* to) {
  for (; from + 8 <= to; from += 8) {
    std::uint64_t eight = 0;
    std::memcpy(&eight, from, sizeof eight);
    if (eight != 0) return false;
  }
  for (; from < to; ++from)
    if (*from != 0) return false;
  return true;
}

}  // namespace

void Tile::normalize_material(std::size_t near) {
  const std::uint8_t* mid = material.data() + std::min(near, material.size());
  if (all_zero(mid, material.data() + material.size()) && all_zero(material.data(), mid))
    std::vector<std::uint8_t>().swap(material);  // frees it
}

void Tile::normalize_layers(std::size_t near) {
  const auto none = [](double d) { return d == kNoLayer; };
  const auto from = layer_boundary.begin() + static_cast<std::ptrdiff_t>(std::min(near, layer_boundary.size()));
  if (std::all_of(from, layer_boundary.end(), none) && std::all_of(layer_boundary.begin(), from, none)) {
    std::vector<double>().swap(layer_boundary);
    std::vector<std::uint8_t>().swap(layer_lower);
  }
}

std::size_t Tile::bytes() const {
  return sizeof(Tile) + capacity_bytes(height, sinkage, base, material, layer_boundary, layer_lower);
}

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

void TileStore::base_row(std::int64_t i0, std::int64_t j, std::span<double> out) const {
  if (!base_) {
    std::fill(out.begin(), out.end(), base_height_);
    return;
  }
  base_->row(origin_x_, cell_, i0, origin_y_ + static_cast<double>(j) * cell_, out);
}

const Tile* TileStore::find(TileKey key) const {
  const auto it = tiles_.find(key);
  return it == tiles_.end() ? nullptr : it->second.get();
}

Tile* TileStore::find(TileKey key) {
  const auto it = tiles_.find(key);
  return it == tiles_.end() ? nullptr : it->second.get();
}

Tile& TileStore::tile(TileKey key) {
  auto& slot = tiles_[key];
  if (slot) {
    slot->last_used = clock_;
  } else {
    slot = std::make_unique<Tile>(n_);
    // Untouched ground is the base source; sample it once, when the tile is created, a row
    // at a time (a cached base copies it).
    const auto n = static_cast<std::size_t>(n_);
    for (int lj = 0; lj < n_; ++lj)
      base_row(key.tx * n_, key.ty * n_ + lj, std::span(slot->base).subspan(static_cast<std::size_t>(lj) * n, n));
    slot->height = slot->base;
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

void TileStore::read(const GridRect& r, std::span<double> out, bool base) const {
  for_each_run(r, [&](const Tile* t, const TileRun& run) {
    double* dst = out.data() + static_cast<std::size_t>(run.y) * static_cast<std::size_t>(r.nx) + run.x;
    if (t) {
      const std::vector<double>& field = base ? t->base : t->height;
      std::copy_n(field.data() + run.local, run.count, dst);
    } else {
      base_row(r.i0 + run.x, r.j0 + run.y, std::span(dst, static_cast<std::size_t>(run.count)));
    }
  });
}

int TileStore::largest_material(std::span<const TileKey> skip) const {
  int largest = 0;
  for (const auto& [key, tile] : tiles_)
    if (!std::binary_search(skip.begin(), skip.end(), key)) {
      for (const std::uint8_t m : tile->material) largest = std::max(largest, static_cast<int>(m));
      for (std::size_t k = 0; k < tile->layer_lower.size(); ++k)
        if (tile->layer_boundary[k] < kNoLayer) largest = std::max(largest, static_cast<int>(tile->layer_lower[k]));
    }
  return largest;
}

std::vector<TileKey> TileStore::painted_since(std::uint64_t g) const {
  std::vector<TileKey> keys;
  if (g >= last_painted_) return keys;  // nothing painted since: no pass over the tiles (asked every substep)
  for (const auto& [key, tile] : tiles_)
    if (tile->painted_at > g) keys.push_back(key);
  std::sort(keys.begin(), keys.end());
  return keys;
}

namespace {
/// Whether `outer` holds every point of the non-empty `inner`.
bool holds(const GridRect& outer, const GridRect& inner) {
  return inner.i0 >= outer.i0 && inner.j0 >= outer.j0 && inner.i1() <= outer.i1() && inner.j1() <= outer.j1();
}
}  // namespace

void TileStore::mark_changed(TileKey key, Tile& t, const GridRect& local) {
  // A grain landing marks its one column, most often in a tile already marked there this
  // generation: when both the pending rectangle and this generation's log entry already
  // hold it, widening them would change nothing.
  if (t.changed_at == generation_ && !local.empty() && !t.changed.empty() && holds(t.changed, local) &&
      holds(log_[t.log_entry].local, local))
    return;
  if (t.changed.empty()) dirty_keys_.push_back(key);
  t.changed = bounding(t.changed, local);
  log_change(key, t, local);
}

void TileStore::log_change(TileKey key, Tile& t, const GridRect& local) {
  if (t.changed_at == generation_) {  // this generation's entry for the tile: widen it
    ChangeEntry& e = log_[t.log_entry];
    e.local = bounding(e.local, local);
    return;
  }
  t.changed_at = generation_;
  t.log_entry = log_.size();
  log_.push_back({generation_, key, local});
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

GridRect TileStore::whole_tile(TileKey key) const { return {key.tx * n_, key.ty * n_, n_, n_}; }

std::vector<GridRect> TileStore::changed_since(std::uint64_t g) const {
  std::vector<GridRect> rects;
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
    const TileKey key = entries[k].key;
    GridRect box = entries[k].local;
    for (++k; k < entries.size() && entries[k].key == key; ++k) box = bounding(box, entries[k].local);
    rects.push_back(box.shifted(key.tx * n_, key.ty * n_));
  }
  return rects;
}

std::vector<GridRect> TileStore::take_changed() {
  std::sort(dirty_keys_.begin(), dirty_keys_.end());
  std::vector<GridRect> rects;
  rects.reserve(dirty_keys_.size());
  for (const TileKey& key : dirty_keys_) {
    const auto it = tiles_.find(key);
    if (it == tiles_.end() || it->second->changed.empty()) continue;
    Tile& t = *it->second;
    rects.push_back(t.changed.shifted(key.tx * n_, key.ty * n_));
    t.changed = {};
  }
  dirty_keys_.clear();
  return rects;
}

bool TileStore::adopt(TileKey key, std::unique_ptr<Tile> t) {
  Tile& added = *t;
  added.last_used = clock_;
  if (added.layered()) layered_ = true;
  if (!tiles_.emplace(key, std::move(t)).second) return false;
  mark_changed(key, added, {0, 0, n_, n_});
  return true;
}

bool TileStore::releasable(Tile& t, std::int64_t idle_steps) const {
  // Only tiles whose heights never changed since they were sampled from the base (so no
  // observer of changed_since() can hold a view of them that differs from the base; loaded
  // tiles count as changed) and that were never painted (painted back to all 0, a soil
  // delta still has to send it): releasing one changes nothing anyone can see.
  if (!t.changed.empty() || t.changed_at != 0 || t.painted_at != 0 || clock_ - t.last_used < idle_steps ||
      t.kept_at == t.last_used)
    return false;
  if (t.holds_only_base()) return true;
  t.kept_at = t.last_used;  // unchanged until a step uses it again: no need to compare again
  return false;
}

std::size_t TileStore::release_idle(std::int64_t idle_steps) {
  if (clock_ % kReleaseScanTicks != 0) return 0;
  std::size_t released = 0;
  // Each tile's fate depends on that tile alone, so the map's order does not matter.
  for (auto it = tiles_.begin(); it != tiles_.end();) {
    if (releasable(*it->second, idle_steps)) {
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
  std::size_t total = tiles_.bucket_count() * sizeof(void*) + capacity_bytes(dirty_keys_, log_);
  for (const auto& entry : tiles_) total += kNodeBytes + entry.second->bytes();
  return total;
}

}  // namespace shore::terrain
