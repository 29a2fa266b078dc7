#pragma once
// The Bullet side of the deformable ground: btHeightfieldTerrainShape tiles created on
// demand around bodies and kept equal to the terrain's heights.
//
// Tile (tx, ty) holds vertices for columns [tx T, tx T + T] x [ty T, ty T + T] (T, the
// tile size, is the terrain's TerrainSettings::tile_columns): neighbouring tiles share their
// edge vertices, so there is no seam.
// Each substep the changed columns are copied into the tiles' float buffers in place;
// contact points whose terrain-side point lies in a changed cell are removed (Bullet
// refreshes cached points from their local positions, so a body would otherwise hover
// over lowered ground) and the bodies there are woken. A rise is capped per substep so
// raised ground (a rim) cannot jump over a body; the tile catches up on later substeps.
//
// A painted terrain (Terrain::set_palette, paint_*) gives the bodies Bullet collides with the
// tiles each column's Material::friction: a tile all of one friction takes it as its
// object's friction (no per-contact work), a tile of several keeps one per vertex and each
// contact takes its nearest vertex's (HeightfieldTile::set_vertex_friction). Repaints and
// palette changes are followed at push().

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <unordered_map>
#include <vector>

#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>

#include "shore/bullet/config.h"
#include "shore/bullet/ground_frame.h"
#include "shore/bullet/heightfield_tile.h"
#include "shore/core/byte_io.h"
#include "shore/terrain/terrain.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

/// A world-space rectangle (m), x in [x0, x1) and y in [y0, y1). Default: everywhere.
struct Region {
  static constexpr double kUnbounded = 1e30;  ///< m: an edge this far out is no edge
  double x0 = -kUnbounded, y0 = -kUnbounded, x1 = kUnbounded, y1 = kUnbounded;
  [[nodiscard]] bool contains(double x, double y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
  /// True if no edge is set (the default): nothing is outside.
  [[nodiscard]] bool everywhere() const {
    return x0 <= -kUnbounded && y0 <= -kUnbounded && x1 >= kUnbounded && y1 >= kUnbounded;
  }
  /// True if some point lies in both (edges are half-open: regions that only touch do not).
  [[nodiscard]] bool overlaps(const Region& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
};

/// The tile size is the terrain's: one tile per TerrainSettings::tile_columns columns a side.
struct TerrainTilesSettings {
  double headroom = 0.5;                ///< m a tile can hold above its highest untouched ground (rims), > 0
  double max_rise_per_substep = 0.002;  ///< m, > 0: cap on how far ground may rise in one substep
  /// Rigid ground's tiles get Bullet's internal-edge info (HeightfieldTile::smooth_internal_edges),
  /// so a box slides over them as over one face instead of catching on triangle edges.
  bool smooth_rigid_edges = true;
  /// Columns per triangle edge that soft ground's tiles give Bullet's convex contacts and
  /// sweeps (HeightfieldTileSettings::contact_stride): what meets them there is only what
  /// the coupling does not serve (a character controller's capsule, bodies not added), and a
  /// capsule on 1 to 2 cm columns spends most of its substep in GJK over thousands of
  /// triangles. 1 (default): every column. 2 or 4: the surface sampled every 2nd or 4th
  /// column, 4 or 16 times fewer triangles; footprints and ruts narrower than the stride
  /// are bridged. Ray casts (raycast vehicles) and rigid ground (which carries added bodies
  /// through Bullet) always see every column. >= 1 and dividing TerrainSettings::tile_columns.
  int contact_stride = 1;
  void validate() const;
};

/// Whether `object` is a heightfield tile of some Shore terrain coupling (tiles are static
/// btRigidBodys; a function listing a world's bodies skips them with this).
[[nodiscard]] bool is_terrain_tile(const btCollisionObject* object) noexcept;

class TerrainTiles {
 public:
  TerrainTiles(btCollisionWorld& world, const terrain::Terrain& terrain, const TerrainTilesSettings& settings);
  ~TerrainTiles();
  TerrainTiles(const TerrainTiles&) = delete;
  TerrainTiles& operator=(const TerrainTiles&) = delete;

  /// Creates the tiles (if missing) that cover the world box [x0, x1] x [y0, y1], limited
  /// to tiles that overlap the allowed region (set_region). Returns how many were created.
  int ensure_cover(double x0, double y0, double x1, double y1);
  /// Only tiles overlapping this region are ever created (default: everywhere).
  void set_region(const Region& region) { region_ = region; }
  /// Where the terrain lies in the world (default: Z up). Tiles are placed through it; the
  /// boxes ensure_cover takes are in the terrain's own coordinates. Set it before the first
  /// tile is made.
  void set_frame(const GroundFrame& frame);

  /// Copies the given changed columns (and any tile still catching up) from the terrain into
  /// the tiles, removes stale contact points there and wakes the bodies. Returns the
  /// number of vertices written.
  std::int64_t push(std::span<const GridRect> changed);

  /// Called by push() with the terrain's changed columns before they are copied (a renderer
  /// uploads just these); empty: nobody listens. One observer; setting another replaces it.
  using PushObserver = std::function<void(std::span<const GridRect> changed)>;
  void set_push_observer(PushObserver observer) { observer_ = std::move(observer); }

  /// Removes every tile from the world and forgets it (a detaching coupling).
  void remove_all();
  [[nodiscard]] bool is_tile(const btCollisionObject* object) const noexcept { return is_terrain_tile(object); }
  [[nodiscard]] std::size_t count() const noexcept { return tiles_.size(); }
  /// Vertices clamped to a tile's height range so far (should stay 0; raise headroom if not).
  [[nodiscard]] std::int64_t clamped_vertices() const noexcept { return clamped_; }
  /// Broadphase group of tiles created from now on (default StaticFilter).
  void set_collision_group(int group) { group_ = group; }
  /// Sets the friction of every tile, present and future: of the columns of palette entry 0
  /// on a painted terrain (the others take their entry's Material::friction).
  void set_friction(double friction);

  /// The tiles for a checkpoint (TerrainCoupling::save_state): which exist, their height
  /// bounds, heights and lagging vertices, in key order.
  void save_state(ByteWriter& w) const;
  /// Makes exactly the saved tiles exist, as saved. The tiles are the last thing in r:
  /// everything is read and checked (FileError) before any tile changes.
  void restore_state(ByteReader& r);

 private:
  struct Tile {
    std::unique_ptr<HeightfieldTile> field;
    std::int64_t i0 = 0, j0 = 0;  // first column
    GridRect lag;                 // vertices a capped rise left below the terrain (tile-local; empty: none)
  };
  static std::uint64_t key(std::int64_t tx, std::int64_t ty) noexcept;
  Tile& create(std::int64_t tx, std::int64_t ty);
  /// The tiles' contact stride: the settings' on soft ground; 1 on rigid ground, which
  /// carries added bodies through Bullet.
  [[nodiscard]] int contact_stride() const noexcept;
  /// A tile with these bounds and heights ((T + 1)^2, row-major) added to the world, made
  /// or restored, with contact_stride().
  Tile& add(std::int64_t tx, std::int64_t ty, HeightfieldTileSettings hs, std::span<const double> heights);
  /// Copies the terrain's heights of `columns` that are the tile's vertices; returns how many.
  std::int64_t copy_rect(Tile& tile, const GridRect& columns);
  void drop_stale_contacts(const GridRect& columns);
  /// Each palette entry's friction as the tiles give it (entry 0: friction_); empty when
  /// every column has friction_ (one entry, or all of the same friction).
  [[nodiscard]] std::vector<double> palette_friction() const;
  /// The tile's friction from the map: one for the object, or one per vertex.
  void paint_friction(Tile& tile);
  /// Repaints and palette changes since the last push, into the tiles' friction.
  void follow_map();

  btCollisionWorld& world_;
  const terrain::Terrain& terrain_;
  TerrainTilesSettings settings_;
  double friction_;
  std::unordered_map<std::uint64_t, Tile> tiles_;
  std::int64_t clamped_ = 0;
  Region region_;
  GroundFrame frame_;
  bool framed_ = false;  // the frame is not the identity
  int group_ = btBroadphaseProxy::StaticFilter;
  std::vector<double> scratch_;        // heights of the rectangle being copied
  std::vector<double> frictions_;      // palette_friction() as the tiles have it
  std::uint64_t painted_seen_ = 0;     // the terrain generation whose paint the tiles have
  std::vector<std::uint8_t> indices_;  // scratch: a tile's vertices' palette indices
  PushObserver observer_;
};

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
