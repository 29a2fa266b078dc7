// Tiles and sleeping: the tile size never changes the bits; a sleeping surface where
// nothing sleeps is the dense grid bit for bit; where tiles sleep the heights stay within
// the sleep threshold of the dense grid's; arriving waves wake tiles; sleeping tiles are
// in the state hash; a 1 km lake is created at once and costs memory only where it moved.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "shore/water/surface.h"

using namespace shore::water;

namespace {

SurfaceSettings basin(SurfaceMode mode, int n, int tile, bool sleep) {
  PhysicalParameters p;
  p.cell = 0.05;
  p.depth = 0.5;
  p.damping_time = 1.0;
  SurfaceSettings s = SurfaceSettings::physical(p, n, n + 7);  // not square, not a multiple of the tile
  s.mode = mode;
  s.boundary = Boundary::vertical_only;
  s.sleep.enabled = sleep;
  s.sleep.tile = tile;
  s.threads = 1;
  return s;
}

void island_and_drops(Surface& s) {
  for (int j = 30; j < 36; ++j)
    for (int i = 40; i < 44; ++i) s.set_fixed(i, j, true);
  s.set_constraint(12, 50, NodeConstraint::vertical_only);
  s.disturb(Disturbance::point_height(s.node_x(25), s.node_y(20), 0.2, 0.05));
  s.disturb(Disturbance::point_velocity(s.node_x(60), s.node_y(55), 0.1, 0.3));
  s.disturb(Disturbance::area_height(s.node_x(50), s.node_y(15), 0.3, 0.2, 0.05, -0.02));
}

std::string mode_name(SurfaceMode m) { return m == SurfaceMode::full_3d ? "Full3d" : "VerticalOnly"; }

class TileSize : public ::testing::TestWithParam<SurfaceMode> {};

TEST_P(TileSize, NeverChangesTheBits) {
  std::uint64_t first = 0;
  for (int tile : {8, 32, 128}) {
    Surface s(basin(GetParam(), 77, tile, false));
    island_and_drops(s);
    s.disturb(Disturbance::point_height(s.node_x(38), s.node_y(40), 0.1, 1.0));  // violent: 20 h
    for (int k = 0; k < 150; ++k) s.step(1.0 / 240);
    if (tile == 8) first = s.state_hash();
    EXPECT_EQ(s.state_hash(), first) << "tile " << tile;
  }
}

TEST_P(TileSize, SleepingSurfaceWhereNothingSleepsIsTheDenseGrid) {
  Surface dense(basin(GetParam(), 77, 16, false));
  Surface sleeping(basin(GetParam(), 77, 16, true));
  for (Surface* s : {&dense, &sleeping}) {
    island_and_drops(*s);
    s->disturb(Disturbance::area_velocity(s->node_x(38), s->node_y(41), 2.0, 2.0, 0.1, 0.05));  // everywhere
  }
  for (int k = 0; k < 100; ++k) {
    dense.step(1.0 / 240);
    sleeping.step(1.0 / 240);
    ASSERT_EQ(sleeping.tile_stats().awake, sleeping.tile_stats().tiles) << "a tile slept at substep " << k;
  }
  EXPECT_EQ(dense.state_hash(), sleeping.state_hash());
}

INSTANTIATE_TEST_SUITE_P(Modes, TileSize, ::testing::Values(SurfaceMode::vertical_only, SurfaceMode::full_3d),
                         [](const ::testing::TestParamInfo<SurfaceMode>& c) { return mode_name(c.param); });

/// Largest |height difference| between two surfaces of the same grid.
double largest_difference(const Surface& a, const Surface& b) {
  const DenseState x = a.dense_state(), y = b.dense_state();
  double m = 0.0;
  for (std::size_t k = 0; k < x.uz.size(); ++k) m = std::max(m, std::abs(x.uz[k] - y.uz[k]));
  return m;
}

class Sleeping : public ::testing::TestWithParam<SurfaceMode> {};

// A ring spreads over a patch of open water and leaves it (damping time 1 s): tiles the
// ring has left fall asleep, tiles it reaches wake. Against the dense grid the heights stay within
// the sleep threshold all along, and the sleeping surface steps far fewer nodes.
TEST_P(Sleeping, StaysWithinTheThresholdOfTheDenseGrid) {
  SurfaceSettings set = basin(GetParam(), 161, 16, true);
  set.boundary = Boundary::open;  // the ring leaves (a patch of a lake)
  set.sleep.height = 2e-6;        // m: the threshold under test (4e-5 h)
  Surface sleeping(set);
  set.sleep.enabled = false;
  Surface dense(set);
  for (Surface* s : {&sleeping, &dense}) s->disturb(Disturbance::point_height(s->node_x(40), s->node_y(45), 0.1, 0.01));
  EXPECT_LT(sleeping.tile_stats().created, sleeping.tile_stats().tiles) << "far tiles exist before the ring gets there";
  double worst = 0.0;
  std::int64_t stepped = 0, dense_stepped = 0;
  bool far_woke = false;
  for (int k = 0; k < 2400; ++k) {  // 10 s
    sleeping.step(1.0 / 240);
    dense.step(1.0 / 240);
    stepped += sleeping.tile_stats().awake_nodes;
    dense_stepped += dense.tile_stats().awake_nodes;
    far_woke = far_woke || sleeping.awake(150, 160);
    if (k % 40 == 0) worst = std::max(worst, largest_difference(sleeping, dense));
  }
  EXPECT_TRUE(far_woke) << "the ring never woke the far corner";
  EXPECT_LE(worst, sleeping.sleep_height()) << "height error";
  EXPECT_LT(stepped, dense_stepped / 2) << "sleeping saved little";
  EXPECT_LT(sleeping.tile_stats().awake, sleeping.tile_stats().tiles / 4) << "still awake at the end";
  RecordProperty("height_error_over_threshold", std::to_string(worst / sleeping.sleep_height()));
  RecordProperty("stepped_fraction", std::to_string(double(stepped) / double(dense_stepped)));
}

INSTANTIATE_TEST_SUITE_P(Modes, Sleeping, ::testing::Values(SurfaceMode::vertical_only, SurfaceMode::full_3d),
                         [](const ::testing::TestParamInfo<SurfaceMode>& c) { return mode_name(c.param); });

TEST(Sleeping, SleepingTilesAreInTheStateHash) {
  SurfaceSettings set = basin(SurfaceMode::vertical_only, 97, 16, true);
  Surface a(set), b(set);
  for (Surface* s : {&a, &b}) s->disturb(Disturbance::point_height(s->node_x(20), s->node_y(20), 0.1, 0.01));
  b.add_height(80, 90, 0.25 * b.sleep_height());  // a residue below the threshold, far away
  for (int k = 0; k < 2400; ++k) {
    a.step(1.0 / 240);
    b.step(1.0 / 240);
  }
  ASSERT_FALSE(b.awake(80, 90)) << "the far tile should sleep by now";
  EXPECT_NE(a.state_hash(), b.state_hash());
}

TEST(Sleeping, DisturbancesAndWakeWakeTheirTiles) {
  Surface s(basin(SurfaceMode::vertical_only, 97, 16, true));
  EXPECT_EQ(s.tile_stats().created, 0);
  EXPECT_FALSE(s.awake(50, 50));
  s.wake(s.node_x(50), s.node_y(50), s.node_x(51), s.node_y(51));
  EXPECT_TRUE(s.awake(50, 50));
  EXPECT_TRUE(s.awake(50 + 16, 50)) << "neighbours wake too";
  EXPECT_FALSE(s.awake(90, 10));
  for (int k = 0; k < 64; ++k) s.step(1.0 / 240);
  EXPECT_FALSE(s.awake(50, 50)) << "nothing moves: the tiles fall asleep again";
  s.disturb(Disturbance::point_velocity(s.node_x(90), s.node_y(10), 0.1, 0.1));
  EXPECT_TRUE(s.awake(90, 10));
}

// A 1 km x 1 km lake at 10 cm (100 million nodes): created at once, a splash in the middle
// costs memory and time in proportion to the tiles it woke.
TEST(Lake, CreationAllocatesNothingDenseAndMemoryFollowsTheWokenArea) {
  PhysicalParameters p;
  p.cell = 0.1;
  p.depth = 2.0;
  SurfaceSettings set = SurfaceSettings::physical(p, 10001, 10001);
  set.mode = SurfaceMode::vertical_only;
  set.boundary = Boundary::open;
  set.threads = 1;
  // Creation is instant because nothing dense is allocated (timed in shore-bench, not here:
  // a wall-clock bound fails on a loaded machine).
  Surface lake(set);
  EXPECT_LT(lake.tile_stats().memory_bytes, std::size_t{1} << 20) << "an empty lake should cost under 1 MB";
  lake.disturb(Disturbance::point_height(500.0, 500.0, 0.5, 0.05));
  for (int k = 0; k < 240; ++k) lake.step(1.0 / 60);
  const TileStats st = lake.tile_stats();
  const double woken_nodes = double(st.ever_awake) * st.tile * st.tile;
  const double dense_bytes = woken_nodes * 17.0;  // a dense grid's state of that area: 2 doubles and a flag
  EXPECT_GT(st.awake, 0);
  EXPECT_LT(double(st.ever_awake), 0.01 * double(st.tiles)) << "the splash woke too much";
  EXPECT_LE(double(st.memory_bytes), 5.0 * dense_bytes) << st.memory_bytes << " bytes for " << woken_nodes << " nodes";
  EXPECT_NE(lake.height(5000, 5000 + 40), 0.0) << "the ring spread";
  RecordProperty("memory_over_dense", std::to_string(double(st.memory_bytes) / dense_bytes));
}

// The memory tile_stats reports is kept as a running count (it no longer walks the tiles):
// it must hold at least the created tiles' state (a 3-D node keeps 2 doubles, 4 floats and
// a flag), grow with the constraint masks a constrained tile keeps, and come out the same
// for a surface restored from a saved state once both have stepped.
TEST(Memory, CountsEveryCreatedTileAndItsMasks) {
  SurfaceSettings set;
  set.nx = set.ny = 200;
  set.sleep.tile = 16;
  set.threads = 1;
  set.boundary = Boundary::free;  // no constrained node at first (a free 3-D edge is free)
  Surface water(set);
  water.disturb(Disturbance::point_height(100.0, 100.0, 3.0, 0.5));
  water.step(0.3);
  const TileStats before = water.tile_stats();
  const double node_state = 2 * 8 + 4 * 4 + 1;  // bytes
  EXPECT_GE(double(before.memory_bytes), double(before.created) * 16 * 16 * node_state);
  water.set_constraint(100, 100, NodeConstraint::fixed);  // its tile keeps masks from its next substep
  water.step(0.3);
  const TileStats after = water.tile_stats();
  const double grown = double(after.created - before.created) * 16 * 16 * node_state + 16 * 16 * 12;
  EXPECT_GE(double(after.memory_bytes), double(before.memory_bytes) + grown)
      << "the new tiles' state and one tile's masks (8 + 4 bytes a node)";
  Surface restored(set);
  restored.restore_state(water.save_state(), "test");
  water.step(0.3);
  restored.step(0.3);
  EXPECT_EQ(restored.state_hash(), water.state_hash());
  EXPECT_EQ(restored.tile_stats().created, water.tile_stats().created);
  // Within 1 KB (the tile lists' capacities may differ): a tile is about 10 KB, its masks 3 KB.
  EXPECT_NEAR(double(restored.tile_stats().memory_bytes), double(water.tile_stats().memory_bytes), 1024.0);
}

}  // namespace
