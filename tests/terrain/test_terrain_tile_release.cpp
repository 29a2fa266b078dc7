// Idle tiles that hold nothing but the untouched base are released (the memory of a long
// run follows the soil that changed, not everywhere a body went), and recreated
// identically when needed; tiles that differ from the base are never released.
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>

#include "shore/terrain/terrain.h"
#include "terrain_fixtures.h"

using namespace shore::terrain;
using namespace shore::terrain::testing;

namespace {

TerrainSettings small_tiles(int idle_tile_steps) {
  TerrainSettings s;
  s.tile_columns = 16;
  s.threads = 1;
  s.idle_tile_steps = idle_tile_steps;
  return s;
}

/// A ball hovering 1 cm above the soil (inside active_reach: it makes the steps work under
/// it, without touching), moved 2 cm along x per step.
void hover_along_x(Terrain& t, int steps, double from_x = 0.0, double ground = 0.0) {
  for (int k = 0; k < steps; ++k) {
    const double x = from_x + 0.02 * k, r = 0.05;
    const shore::EnvelopeRaster env = sphere_envelope(t, x, 0.0, ground + r + 0.01, r);
    const Imprint im{&env};
    t.step({&im, 1});
    (void)t.take_changed();
  }
}

/// A ball pressed into the soil at (x, 0), then lifted.
void press_at(Terrain& t, double x) {
  for (int k = 1; k <= 4; ++k) {
    const shore::EnvelopeRaster env = sphere_envelope(t, x, 0.0, 0.1 - 0.004 * k, 0.1);
    const Imprint im{&env};
    t.step({&im, 1});
  }
  (void)t.take_changed();
}

bool same_heights(const Terrain& a, const Terrain& b, std::int64_t i0, std::int64_t i1, std::int64_t j0,
                  std::int64_t j1) {
  for (std::int64_t j = j0; j <= j1; ++j)
    for (std::int64_t i = i0; i <= i1; ++i)
      if (a.height(i, j) != b.height(i, j) || a.sinkage(i, j) != b.sinkage(i, j)) return false;
  return true;
}

}  // namespace

TEST(TileRelease, AHoveringBodyLeavesNoTrailOfTiles) {
  Terrain kept(small_tiles(0)), released(small_tiles(128));
  hover_along_x(kept, 300);
  hover_along_x(released, 300);
  const std::size_t kept_tiles_at_300 = kept.tile_count(), released_at_300 = released.tile_count();
  hover_along_x(kept, 300, 6.0);
  hover_along_x(released, 300, 6.0);
  // 12 m of travel over 16 cm tiles, two rows of them: without release every tile passed stays.
  EXPECT_GT(kept.tile_count(), kept_tiles_at_300 + 60);
  // With it, only the tiles of the last 128 steps (2.6 m) and those not yet scanned.
  EXPECT_LE(released.tile_count(), released_at_300 + 4);
  EXPECT_LT(released.tile_count(), kept.tile_count() / 2);
  EXPECT_LT(released.memory_bytes(), kept.memory_bytes());
  // The soil is the same, and so is its hash: a released tile equals no tile.
  EXPECT_EQ(released.state_hash(), kept.state_hash());
  EXPECT_EQ(released.state_hash(), Terrain(small_tiles(0)).state_hash());
  EXPECT_TRUE(same_heights(kept, released, -20, 1220, -20, 20));
  EXPECT_EQ(released.volume().total(), kept.volume().total());
}

TEST(TileRelease, ReleasedTilesAreRecreatedIdentically) {
  // Hover away and back: the second pass recreates released tiles, and a press there
  // gives what it gives on a terrain that never released anything.
  Terrain kept(small_tiles(0)), released(small_tiles(64));
  for (Terrain* t : {&kept, &released}) {
    hover_along_x(*t, 200);
    hover_along_x(*t, 200, 4.0);  // far from the start for 200 steps
    press_at(*t, 0.5);
  }
  EXPECT_LT(released.tile_count(), kept.tile_count());
  EXPECT_EQ(released.state_hash(), kept.state_hash());
  EXPECT_TRUE(same_heights(kept, released, 20, 80, -20, 20));
}

TEST(TileRelease, TilesThatDifferFromTheBaseAreNeverReleased) {
  Terrain t(small_tiles(64));
  press_at(t, 0.0);
  const std::uint64_t hash = t.state_hash();
  Terrain reference(small_tiles(0));
  press_at(reference, 0.0);
  // A long while with the body elsewhere (5 m away): the crater's tiles stay idle.
  hover_along_x(t, 1000, 5.0);
  hover_along_x(reference, 1000, 5.0);
  EXPECT_EQ(t.state_hash(), reference.state_hash());
  EXPECT_TRUE(same_heights(t, reference, -20, 20, -20, 20));
  bool crater = false;
  for (std::int64_t i = -10; i <= 10; ++i) crater |= t.height(i, 0) < 0.0;
  EXPECT_TRUE(crater) << "the crater is still there";
  EXPECT_NE(hash, Terrain(small_tiles(0)).state_hash());
}

TEST(TileRelease, LoadedTilesAreKeptOnAnyBase) {
  // Tiles saved over flat ground at 0, loaded over ground at 1 m: they hold the saved
  // heights (0), which are not this base; releasing them would raise the ground by 1 m.
  Terrain t(small_tiles(64));
  hover_along_x(t, 10);  // tiles holding the base only
  const std::size_t tiles = t.tile_count();
  ASSERT_GT(tiles, 0u);
  Terrain loaded = Terrain::load_bytes(t.save_bytes(), "memory", std::make_shared<FlatHeight>(1.0));
  EXPECT_EQ(loaded.tile_count(), tiles);
  hover_along_x(loaded, 300, 20.0, 1.0);
  EXPECT_EQ(loaded.height(0, 0), 0.0);
  EXPECT_EQ(loaded.height(5, 0), 0.0);
  EXPECT_EQ(loaded.height(0, 100), 1.0) << "elsewhere the new base";
  // On the same base too: a loaded tile counts as changed (an observer of the changes may
  // not have seen it yet), so it is kept, unlike the tiles this run made and left alone.
  Terrain same = Terrain::load_bytes(t.save_bytes(), "memory");
  hover_along_x(same, 300, 20.0);
  for (std::int64_t i = 0; i < 64; ++i) ASSERT_EQ(same.height(i, 0), 0.0);
  EXPECT_EQ(loaded.tile_count(), same.tile_count());
  EXPECT_GE(same.tile_count(), tiles);
  EXPECT_EQ(same.height(0, 0), 0.0);
}
