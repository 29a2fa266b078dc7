#include "shore/bullet/terrain_tiles.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <BulletCollision/BroadphaseCollision/btDispatcher.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

#include "shore/core/error.h"
#include "shore/core/floor_div.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

void TerrainTilesSettings::validate() const {
  const Check c{"bullet.TerrainTilesSettings"};
  c.positive("headroom", headroom);
  c.positive("max_rise_per_substep", max_rise_per_substep);
  c.at_least("contact_stride", contact_stride, 1);
}

TerrainTiles::TerrainTiles(btCollisionWorld& world, const terrain::Terrain& terrain,
                           const TerrainTilesSettings& settings)
    : world_(world), terrain_(terrain), settings_(settings), friction_(terrain.settings().material.friction) {
  settings_.validate();
  if (const int T = terrain.settings().tile_columns; T % settings_.contact_stride != 0)
    throw InvalidSetting("bullet.TerrainTilesSettings.contact_stride", std::to_string(settings_.contact_stride),
                         "must divide the terrain's tile_columns (" + std::to_string(T) + ")");
  frictions_ = palette_friction();  // a terrain painted before its coupling: tiles are made painted
  painted_seen_ = terrain.generation();
}

TerrainTiles::~TerrainTiles() { remove_all(); }

void TerrainTiles::remove_all() {
  for (auto& [k, tile] : tiles_) world_.removeCollisionObject(tile.field->object());
  tiles_.clear();
}

std::uint64_t TerrainTiles::key(std::int64_t tx, std::int64_t ty) noexcept {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(tx)) << 32) | static_cast<std::uint32_t>(ty);
}

namespace {
constexpr int kTileTag = 0x5e0e71;  // user index 2 of every tile object
}  // namespace

bool is_terrain_tile(const btCollisionObject* object) noexcept {
  // Tiles are tagged through their user index (cheaper than a lookup).
  return object != nullptr && object->getUserIndex2() == kTileTag;
}

void TerrainTiles::set_friction(double friction) {
  friction_ = friction;
  frictions_ = palette_friction();
  for (auto& [k, tile] : tiles_) {
    tile.field->object()->setFriction(btScalar(friction));
    if (!frictions_.empty() || tile.field->has_vertex_friction()) paint_friction(tile);
  }
}

std::vector<double> TerrainTiles::palette_friction() const {
  const std::span<const terrain::Material> palette = terrain_.palette();
  std::vector<double> f(palette.size(), friction_);
  bool uniform = true;
  for (std::size_t k = 1; k < palette.size(); ++k) {
    f[k] = palette[k].friction;
    uniform = uniform && f[k] == friction_;
  }
  if (uniform) f.clear();
  return f;
}

// Every vertex's friction from its column's palette entry; a tile of one friction keeps it
// as its object's (Bullet's plain contact), one of several keeps it per vertex.
void TerrainTiles::paint_friction(Tile& tile) {
  HeightfieldTile& field = *tile.field;
  if (frictions_.empty()) {
    if (field.has_vertex_friction()) field.set_vertex_friction({});
    field.object()->setFriction(btScalar(friction_));
    return;
  }
  const int n = field.columns();
  indices_.resize(static_cast<std::size_t>(n) * static_cast<std::size_t>(n));
  terrain_.material_indices({tile.i0, tile.j0, n, n}, indices_);
  const std::uint8_t first = indices_[0];
  const bool one = std::all_of(indices_.begin(), indices_.end(), [&](std::uint8_t m) { return m == first; });
  if (one) {
    if (field.has_vertex_friction()) field.set_vertex_friction({});
    field.object()->setFriction(btScalar(frictions_[first]));
    return;
  }
  std::vector<btScalar> friction(indices_.size());
  for (std::size_t k = 0; k < indices_.size(); ++k) friction[k] = btScalar(frictions_[indices_[k]]);
  field.object()->setFriction(btScalar(friction_));
  field.set_vertex_friction(std::move(friction));
}

void TerrainTiles::follow_map() {
  const std::uint64_t now = terrain_.generation();
  if (terrain_.palette().size() == 1 && frictions_.empty()) {  // nothing painted differs: no work
    painted_seen_ = now;
    return;
  }
  if (std::vector<double> f = palette_friction(); f != frictions_) {
    frictions_ = std::move(f);
    for (auto& [k, tile] : tiles_) paint_friction(tile);
  } else if (!frictions_.empty()) {
    const int T = terrain_.settings().tile_columns;
    for (const GridRect& r : terrain_.painted_since(painted_seen_))  // soil tiles; ours share their edges
      for (std::int64_t ty = floor_div(r.j0 - 1, T); ty <= floor_div(r.j1() - 1, T); ++ty)
        for (std::int64_t tx = floor_div(r.i0 - 1, T); tx <= floor_div(r.i1() - 1, T); ++tx)
          if (auto it = tiles_.find(key(tx, ty)); it != tiles_.end()) paint_friction(it->second);
  }
  painted_seen_ = now;
}

TerrainTiles::Tile& TerrainTiles::create(std::int64_t tx, std::int64_t ty) {
  const terrain::TerrainSettings& s = terrain_.settings();
  const int T = s.tile_columns;
  const std::int64_t i0 = tx * T, j0 = ty * T;
  // The vertices read in bulk: where no soil tile is yet, a column's heights come from the
  // base source, which may be costly (a noise); read a column at a time (bedrock, base and
  // height, then height again), it was asked four times instead of twice.
  const GridRect vertices{i0, j0, T + 1, T + 1};
  std::vector<double> heights(vertices.size()), base(vertices.size());
  std::vector<std::uint8_t> mats(vertices.size());
  terrain_.heights(vertices, heights);
  terrain_.base_heights(vertices, base);
  terrain_.material_indices(vertices, mats);
  const std::span<const terrain::Material> palette = terrain_.palette();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    // Terrain::bedrock: a rigid entry on deforming ground has its bedrock at its surface.
    const bool rigid_patch = palette[mats[k]].rigid && !s.material.rigid;
    lo = std::min(lo, base[k] - (rigid_patch ? 0.0 : s.material.soil_depth));
    hi = std::max(hi, std::max(base[k], heights[k]));
  }
  HeightfieldTileSettings hs;
  hs.columns = T + 1;
  hs.cell = s.cell;
  hs.origin_x = terrain_.column_x(i0);
  hs.origin_y = terrain_.column_y(j0);
  hs.min_height = lo - 0.01;
  hs.max_height = hi + settings_.headroom;
  hs.initial_height = hi;
  hs.friction = friction_;
  return add(tx, ty, hs, heights);
}

TerrainTiles::Tile& TerrainTiles::add(std::int64_t tx, std::int64_t ty, HeightfieldTileSettings hs,
                                      std::span<const double> heights) {
  // Made or restored, a soft tile gives convex queries the stride; rigid ground carries
  // added bodies through Bullet and keeps every column.
  hs.contact_stride = contact_stride();
  const int T = terrain_.settings().tile_columns;
  // A second tile at the same key would leave its collision object in the world after the
  // map refused it; callers check first, this keeps the invariant if one does not.
  if (const auto found = tiles_.find(key(tx, ty)); found != tiles_.end()) return found->second;
  Tile tile;
  tile.i0 = tx * T;
  tile.j0 = ty * T;
  tile.field = std::make_unique<HeightfieldTile>(hs);
  for (int b = 0; b <= T; ++b)
    for (int a = 0; a <= T; ++a) tile.field->set_height(a, b, heights[static_cast<std::size_t>(b) * (T + 1) + a]);
  // Rigid ground never changes: its tiles can carry Bullet's internal-edge info.
  if (terrain_.settings().material.rigid && settings_.smooth_rigid_edges) tile.field->smooth_internal_edges();
  if (!frictions_.empty()) paint_friction(tile);
  tile.field->object()->setUserIndex2(kTileTag);
  if (framed_) tile.field->object()->setWorldTransform(frame_.to_world() * tile.field->object()->getWorldTransform());
  world_.addCollisionObject(tile.field->object(), group_,
                            btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter);
  return tiles_.emplace(key(tx, ty), std::move(tile)).first->second;
}

int TerrainTiles::contact_stride() const noexcept {
  return terrain_.settings().material.rigid ? 1 : settings_.contact_stride;
}

void TerrainTiles::set_frame(const GroundFrame& frame) {
  frame.validate("bullet.TerrainTiles.set_frame(frame)");
  frame_ = frame;
  framed_ = !frame.identity();
}

int TerrainTiles::ensure_cover(double x0, double y0, double x1, double y1) {
  const int T = terrain_.settings().tile_columns;
  // Tiles whose span lies strictly inside the region's edges (a tile touching the region
  // only along its border belongs to the neighbour).
  const double eps = 1e-6 * terrain_.settings().cell;
  x0 = std::max(x0, region_.x0 + eps);
  y0 = std::max(y0, region_.y0 + eps);
  x1 = std::min(x1, region_.x1 - eps);
  y1 = std::min(y1, region_.y1 - eps);
  if (x0 > x1 || y0 > y1) return 0;
  const terrain::TerrainSettings& s = terrain_.settings();
  auto tile_of = [&](double w, double origin) {
    return static_cast<std::int64_t>(std::floor((w - origin) / (s.cell * T)));
  };
  const std::int64_t tx0 = tile_of(x0, s.origin_x), tx1 = tile_of(x1, s.origin_x);
  const std::int64_t ty0 = tile_of(y0, s.origin_y), ty1 = tile_of(y1, s.origin_y);
  int created = 0;
  for (std::int64_t ty = ty0; ty <= ty1; ++ty)
    for (std::int64_t tx = tx0; tx <= tx1; ++tx)
      if (!tiles_.contains(key(tx, ty))) {
        create(tx, ty);
        ++created;
      }
  return created;
}

std::int64_t TerrainTiles::copy_rect(Tile& tile, const GridRect& columns) {
  const int T = terrain_.settings().tile_columns;
  // The tile's vertices: its columns [i0, i0 + T] x [j0, j0 + T] (edges shared with neighbours).
  const GridRect rect = intersection(columns, {tile.i0, tile.j0, T + 1, T + 1});
  if (rect.empty()) return 0;
  const std::int64_t a0 = rect.i0 - tile.i0, b0 = rect.j0 - tile.j0;
  const auto width = static_cast<std::size_t>(rect.nx);
  // The scratch only grows: resized to each rectangle, it would zero what it regrew before
  // the heights overwrite it.
  const std::size_t n = width * static_cast<std::size_t>(rect.ny);
  if (scratch_.size() < n) scratch_.resize(n);
  const std::span<double> heights(scratch_.data(), n);
  terrain_.heights(rect, heights);
  for (int b = 0; b < rect.ny; ++b) {
    // Raised ground may not jump over a body: it rises at most max_rise_per_substep.
    const HeightfieldTile::RowWrite w =
        tile.field->set_row(int(a0), int(b0) + b, heights.subspan(b * width, width), settings_.max_rise_per_substep);
    clamped_ += w.clamped;
    if (w.first_held >= 0)
      tile.lag = bounding(tile.lag, GridRect::spanning(a0 + w.first_held, b0 + b, a0 + w.last_held, b0 + b));
  }
  return static_cast<std::int64_t>(n);
}

std::int64_t TerrainTiles::push(std::span<const GridRect> changed) {
  if (observer_ && !changed.empty()) observer_(changed);
  follow_map();
  const int T = terrain_.settings().tile_columns;
  std::int64_t written = 0;
  // Vertices still catching up with a capped rise.
  for (auto& [k, tile] : tiles_)
    if (!tile.lag.empty()) {
      const GridRect lagging = tile.lag.shifted(tile.i0, tile.j0);
      tile.lag = {};
      written += copy_rect(tile, lagging);
      drop_stale_contacts(lagging);
    }
  for (const GridRect& r : changed) {
    if (r.empty()) continue;
    const std::int64_t ci1 = r.i1() - 1, cj1 = r.j1() - 1;
    // Every tile holding a vertex of the rectangle (shared edges belong to two tiles).
    for (std::int64_t ty = floor_div(r.j0 - 1, T); ty <= floor_div(cj1, T); ++ty)
      for (std::int64_t tx = floor_div(r.i0 - 1, T); tx <= floor_div(ci1, T); ++tx) {
        auto it = tiles_.find(key(tx, ty));
        if (it == tiles_.end()) continue;
        Tile& tile = it->second;
        if (r.i0 > tile.i0 + T || ci1 < tile.i0 || r.j0 > tile.j0 + T || cj1 < tile.j0) continue;
        written += copy_rect(tile, r);
      }
    drop_stale_contacts(r);
  }
  return written;
}

void TerrainTiles::drop_stale_contacts(const GridRect& columns) {
  // Contact points over the columns and a triangle's edge around them (a coarse triangle
  // with a changed corner reaches contact_stride cells from it).
  const double margin = terrain_.settings().cell * (terrain_.settings().material.rigid ? 1 : settings_.contact_stride);
  const double x0 = terrain_.column_x(columns.i0) - margin, y0 = terrain_.column_y(columns.j0) - margin;
  const double x1 = terrain_.column_x(columns.i1() - 1) + margin, y1 = terrain_.column_y(columns.j1() - 1) + margin;
  const btTransform to_ground = frame_.to_ground();
  btDispatcher* dispatcher = world_.getDispatcher();
  const int n = dispatcher->getNumManifolds();
  for (int m = 0; m < n; ++m) {
    btPersistentManifold* manifold = dispatcher->getManifoldByIndexInternal(m);
    const bool tile_is_0 = is_tile(manifold->getBody0());
    if (!tile_is_0 && !is_tile(manifold->getBody1())) continue;
    bool removed = false;
    for (int p = manifold->getNumContacts() - 1; p >= 0; --p) {
      const btManifoldPoint& pt = manifold->getContactPoint(p);
      const btVector3& in_world = tile_is_0 ? pt.m_positionWorldOnA : pt.m_positionWorldOnB;
      const btVector3 on_tile = framed_ ? to_ground(in_world) : in_world;
      if (on_tile.x() >= x0 && on_tile.x() <= x1 && on_tile.y() >= y0 && on_tile.y() <= y1) {
        manifold->removeContactPoint(p);
        removed = true;
      }
    }
    if (removed) {
      auto* body = const_cast<btCollisionObject*>(tile_is_0 ? manifold->getBody1() : manifold->getBody0());
      body->activate(true);
    }
  }
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
