// TerrainTiles: the Bullet heightfield copies of the soil. Raised ground rises at most
// max_rise_per_substep per push and then catches up (only the held-back vertices are
// rewritten); lowered ground drops Bullet's stale contact points there and wakes the body.
#include <gtest/gtest.h>

#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "shore/bullet/terrain_tiles.h"
#include "shore/core/byte_io.h"
#include "shore/core/error.h"
#include "shore/scenes/world.h"
#include "shore/terrain/height_source.h"
#include "shore/terrain/terrain.h"

using namespace shore;

namespace {
terrain::TerrainSettings flat_sand() {
  terrain::TerrainSettings s;
  s.cell = 0.02;
  return s;
}

/// World height Bullet sees at (x, y): a ray straight down onto the tiles.
double bullet_ground(btCollisionWorld& world, double x, double y) {
  const btVector3 from(btScalar(x), btScalar(y), btScalar(2)), to(btScalar(x), btScalar(y), btScalar(-2));
  btCollisionWorld::ClosestRayResultCallback hit(from, to);
  world.rayTest(from, to, hit);
  return hit.hasHit() ? double(hit.m_hitPointWorld.z()) : std::nan("");
}
}  // namespace

TEST(TerrainTiles, RaisedGroundRisesAtMostTheCapPerPushThenCatchesUp) {
  terrain::TerrainSettings s = flat_sand();
  s.tile_columns = 32;  // the tiles take the soil's tile size
  terrain::Terrain soil(s);
  scenes::World world(9.81);
  bullet::TerrainTilesSettings ts;
  ts.max_rise_per_substep = 0.002;
  bullet::TerrainTiles tiles(world.world(), soil, ts);
  ASSERT_EQ(tiles.ensure_cover(0.1, 0.1, 0.5, 0.5), 1);
  // An outside edit raises a 3 x 3 patch by 9 mm.
  for (std::int64_t j = 10; j < 13; ++j)
    for (std::int64_t i = 10; i < 13; ++i) soil.set_height(i, j, 0.009);
  const double x = soil.column_x(11), y = soil.column_y(11);
  const double rises[] = {0.002, 0.004, 0.006, 0.008, 0.009, 0.009};
  std::int64_t written = tiles.push(soil.take_changed());
  EXPECT_EQ(written, 9);
  for (double expected : rises) {
    EXPECT_NEAR(bullet_ground(world.world(), x, y), expected, 1e-5);
    EXPECT_NEAR(bullet_ground(world.world(), soil.column_x(14), y), 0.0, 1e-6);  // untouched
    written = tiles.push({});
    // Only the held-back vertices are copied again, never the whole tile (33 x 33).
    EXPECT_LE(written, 9);
  }
  EXPECT_EQ(written, 0);  // caught up: nothing left to copy
  EXPECT_EQ(tiles.clamped_vertices(), 0);
}

TEST(TerrainTiles, LoweredGroundDropsStaleContactsAndWakesTheBody) {
  terrain::Terrain soil(flat_sand());
  scenes::World world(9.81);
  bullet::TerrainTiles tiles(world.world(), soil, {});
  tiles.ensure_cover(-0.5, -0.5, 0.5, 0.5);
  btRigidBody* box =
      world.add_body(std::make_unique<btBoxShape>(btVector3(0.1f, 0.1f, 0.1f)), 5.0, btVector3(0, 0, btScalar(0.1)));
  for (int k = 0; k < 600 && box->isActive(); ++k) world.step(1.0 / 240);
  ASSERT_FALSE(box->isActive()) << "the box should have gone to sleep on flat ground";
  const double rest = box->getCenterOfMassPosition().z();
  // The soil under the box drops by 5 cm.
  for (std::int64_t j = -8; j <= 8; ++j)
    for (std::int64_t i = -8; i <= 8; ++i) soil.set_height(i, j, -0.05);
  tiles.push(soil.take_changed());
  EXPECT_TRUE(box->isActive());
  int stale = 0;
  btDispatcher* dispatcher = world.world().getDispatcher();
  for (int m = 0; m < dispatcher->getNumManifolds(); ++m)
    stale += dispatcher->getManifoldByIndexInternal(m)->getNumContacts();
  EXPECT_EQ(stale, 0);
  for (int k = 0; k < 240; ++k) world.step(1.0 / 240);
  EXPECT_NEAR(box->getCenterOfMassPosition().z(), rest - 0.05, 0.005);
}

namespace {
/// Ridges: every column with an odd index 4 cm above the others (at 0), 5 cm columns.
class Ridges final : public terrain::HeightSource {
 public:
  [[nodiscard]] double height(double x, double y) const override {
    const auto odd = [](double w) { return std::lround(w / 0.05) % 2 != 0; };
    return odd(x) || odd(y) ? 0.04 : 0.0;
  }
};

terrain::TerrainSettings ridged(const terrain::Material& material) {
  terrain::TerrainSettings s;
  s.cell = 0.05;
  s.tile_columns = 32;
  s.material = material;
  s.base = std::make_shared<Ridges>();
  return s;
}

/// Where a ball (r 0.1 m, not added to any coupling) comes to rest dropped at (0.8, 0.8).
double ball_rest(scenes::World& world) {
  btRigidBody* ball = world.add_body(std::make_unique<btSphereShape>(btScalar(0.1)), 1.0, btVector3(0.8f, 0.8f, 0.3f));
  ball->setRollingFriction(btScalar(0.1));
  for (int k = 0; k < 480; ++k) world.step(1.0 / 240);
  return ball->getCenterOfMassPosition().z();
}
}  // namespace

// Soft tiles made with a contact stride of 2 show a body Bullet collides with the even
// columns (the plane z = 0 here), also once restored from a checkpoint; rigid ground's tiles
// keep every column (the ridges), whatever the stride.
TEST(TerrainTiles, SoftTilesMadeOrRestoredTakeTheContactStrideAndRigidTilesDoNot) {
  bullet::TerrainTilesSettings ts;
  ts.contact_stride = 2;
  terrain::Terrain sand(ridged(terrain::Material::sand())), rock(ridged(terrain::Material::rigid_ground()));
  ByteWriter saved;
  {
    scenes::World world(9.81);
    bullet::TerrainTiles tiles(world.world(), sand, ts);
    tiles.ensure_cover(0.0, 0.0, 1.5, 1.5);
    EXPECT_NEAR(ball_rest(world), 0.1, 0.005) << "m: on the sampled plane";
    tiles.save_state(saved);
  }
  {
    scenes::World world(9.81);
    bullet::TerrainTiles tiles(world.world(), sand, ts);
    ByteReader r(saved.bytes, "tiles");
    tiles.restore_state(r);
    EXPECT_NEAR(ball_rest(world), 0.1, 0.005) << "m: restored, on the sampled plane";
  }
  scenes::World world(9.81);
  bullet::TerrainTiles tiles(world.world(), rock, ts);
  tiles.ensure_cover(0.0, 0.0, 1.5, 1.5);
  EXPECT_GT(ball_rest(world), 0.12) << "m: rigid ground, on the ridges";
}

TEST(TerrainTiles, AContactStrideThatDoesNotDivideTheTileIsRefused) {
  terrain::TerrainSettings s = flat_sand();
  s.tile_columns = 32;
  terrain::Terrain soil(s);
  scenes::World world(9.81);
  bullet::TerrainTilesSettings ts;
  ts.contact_stride = 3;
  try {
    bullet::TerrainTiles tiles(world.world(), soil, ts);
    ADD_FAILURE() << "a contact stride of 3 on tiles of 32 columns was accepted";
  } catch (const InvalidSetting& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("contact_stride"), std::string::npos) << what;
    EXPECT_NE(what.find("32"), std::string::npos) << what;
  }
  ts.contact_stride = 0;
  EXPECT_THROW(bullet::TerrainTiles(world.world(), soil, ts), InvalidSetting);
  ts.contact_stride = 4;
  EXPECT_NO_THROW(bullet::TerrainTiles(world.world(), soil, ts));
}

// A checkpoint's tile list is read whole before any tile changes: one that names the same
// tile twice (or a tile index beyond the 32 bits its key holds) is refused with a message
// naming the tile, and the tiles in the world stay as they were.
TEST(TerrainTiles, RestoreRefusesATileSavedTwiceOrOutOfRange) {
  terrain::TerrainSettings s = flat_sand();
  s.tile_columns = 8;
  terrain::Terrain soil(s);
  scenes::World world(9.81);
  bullet::TerrainTiles tiles(world.world(), soil, {});
  ASSERT_EQ(tiles.ensure_cover(0.01, 0.01, 0.25, 0.1), 2);  // tiles (0, 0) and (1, 0)
  ByteWriter w;
  tiles.save_state(w);
  const int objects = world.world().getNumCollisionObjects();
  // Layout: i32 tile size, i64 clamped, u64 count, then per tile i64 tx, i64 ty, 3 bounds,
  // the heights as u64 count + (T + 1)^2 doubles, 4 i32 of lag.
  const std::size_t header = 4 + 8 + 8, tile = 16 + 24 + 8 + 81 * 8 + 16;
  ASSERT_EQ(w.bytes.size(), header + 2 * tile);
  auto refused = [&](std::int64_t tx, const char* expected) {
    std::vector<unsigned char> bytes = w.bytes;
    std::memcpy(bytes.data() + header + tile, &tx, sizeof tx);  // the second tile's tx
    ByteReader r(bytes, "tiles");
    try {
      tiles.restore_state(r);
      ADD_FAILURE() << "tile index " << tx << " was accepted";
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
    EXPECT_EQ(tiles.count(), 2u);
    EXPECT_EQ(world.world().getNumCollisionObjects(), objects);
  };
  refused(0, "is saved twice");
  refused(std::int64_t{1} << 32, "beyond tile index");  // its key would equal tile (0, 0)'s
  // The unchanged bytes restore, and the world can still step.
  ByteReader r(w.bytes, "tiles");
  tiles.restore_state(r);
  EXPECT_EQ(tiles.count(), 2u);
  world.step(1.0 / 240);
}
