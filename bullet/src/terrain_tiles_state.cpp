// TerrainTiles in a checkpoint (TerrainCoupling::save_state): which tiles exist, their
// height bounds, heights and lagging vertices, in key order.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_set>
#include <vector>

#include "shore/bullet/terrain_tiles.h"
#include "shore/core/byte_io.h"
#include "shore/core/error.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

namespace {
struct SavedTile {
  std::int64_t tx = 0, ty = 0;
  HeightfieldTileSettings settings;
  std::vector<double> heights;
  GridRect lag;
};
}  // namespace

void TerrainTiles::save_state(ByteWriter& w) const {
  const int T = terrain_.settings().tile_columns;
  std::vector<const Tile*> ordered;  // key order: the file does not depend on the map's
  ordered.reserve(tiles_.size());
  for (const auto& [k, tile] : tiles_) ordered.push_back(&tile);
  std::sort(ordered.begin(), ordered.end(),
            [](const Tile* a, const Tile* b) { return a->j0 != b->j0 ? a->j0 < b->j0 : a->i0 < b->i0; });
  w.put(static_cast<std::int32_t>(T)), w.put(clamped_);
  w.put(static_cast<std::uint64_t>(ordered.size()));
  for (const Tile* t : ordered) {
    const HeightfieldTileSettings& s = t->field->settings();
    w.put(t->i0 / T), w.put(t->j0 / T);
    w.put(s.min_height), w.put(s.max_height), w.put(s.initial_height);
    std::vector<double> h(static_cast<std::size_t>(s.columns) * static_cast<std::size_t>(s.columns));
    for (int b = 0; b < s.columns; ++b)
      for (int a = 0; a < s.columns; ++a) h[static_cast<std::size_t>(b) * s.columns + a] = t->field->height(a, b);
    w.put_array(h);
    w.put(static_cast<std::int32_t>(t->lag.i0)), w.put(static_cast<std::int32_t>(t->lag.j0));
    w.put(static_cast<std::int32_t>(t->lag.nx)), w.put(static_cast<std::int32_t>(t->lag.ny));
  }
}

void TerrainTiles::restore_state(ByteReader& r) {
  const int T = terrain_.settings().tile_columns;
  if (const auto saved_T = r.get<std::int32_t>("tile size"); saved_T != T)
    r.fail("tiles of " + std::to_string(saved_T) + " columns, this terrain's are " + std::to_string(T));
  const auto clamped = r.get<std::int64_t>("tiles");
  const auto count = r.get<std::uint64_t>("tile count");
  const std::size_t vertices = static_cast<std::size_t>(T + 1) * static_cast<std::size_t>(T + 1);
  if (count > r.remaining() / (vertices * sizeof(double))) r.fail("tile count " + std::to_string(count) + " overruns");
  std::vector<SavedTile> saved(static_cast<std::size_t>(count));
  for (SavedTile& t : saved) {
    t.tx = r.get<std::int64_t>("tile"), t.ty = r.get<std::int64_t>("tile");
    // A tile's key packs both indices in 32 bits each; beyond that two tiles would share one.
    constexpr std::int64_t kMaxTile = std::numeric_limits<std::int32_t>::max();
    if (t.tx < -kMaxTile || t.tx > kMaxTile || t.ty < -kMaxTile || t.ty > kMaxTile)
      r.fail("tile (" + std::to_string(t.tx) + ", " + std::to_string(t.ty) + ") lies beyond tile index 2^31 - 1");
    HeightfieldTileSettings& s = t.settings;
    s.columns = T + 1;
    s.cell = terrain_.settings().cell;
    s.origin_x = terrain_.column_x(t.tx * T), s.origin_y = terrain_.column_y(t.ty * T);
    s.min_height = r.get<double>("tile bounds"), s.max_height = r.get<double>("tile bounds");
    s.initial_height = r.get<double>("tile bounds");
    s.friction = friction_;
    if (!(s.min_height < s.max_height) || !(s.initial_height >= s.min_height && s.initial_height <= s.max_height))
      r.fail("tile (" + std::to_string(t.tx) + ", " + std::to_string(t.ty) + ") has broken height bounds");
    r.get_array(t.heights, vertices, "tile heights");
    for (double h : t.heights)
      if (!std::isfinite(h))
        r.fail("tile (" + std::to_string(t.tx) + ", " + std::to_string(t.ty) + ") has a non-finite height");
    t.lag.i0 = r.get<std::int32_t>("tile lag"), t.lag.j0 = r.get<std::int32_t>("tile lag");
    t.lag.nx = r.get<std::int32_t>("tile lag"), t.lag.ny = r.get<std::int32_t>("tile lag");
    if (!t.lag.empty() && (t.lag.i0 < 0 || t.lag.j0 < 0 || t.lag.i1() > T + 1 || t.lag.j1() > T + 1))
      r.fail("tile (" + std::to_string(t.tx) + ", " + std::to_string(t.ty) + ") lags outside itself");
  }
  if (r.remaining() != 0) r.fail("bytes after the last tile (corrupt)");
  std::unordered_set<std::uint64_t> keys;
  for (const SavedTile& t : saved)
    if (!keys.insert(key(t.tx, t.ty)).second)
      r.fail("tile (" + std::to_string(t.tx) + ", " + std::to_string(t.ty) + ") is saved twice");
  remove_all();
  clamped_ = clamped;
  // The terrain (loaded before) brings its map: the tiles are made with its friction.
  frictions_ = palette_friction();
  painted_seen_ = terrain_.generation();
  for (const SavedTile& t : saved) {
    Tile& tile = add(t.tx, t.ty, t.settings, t.heights);
    tile.lag = t.lag.empty() ? GridRect{} : t.lag;
  }
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
