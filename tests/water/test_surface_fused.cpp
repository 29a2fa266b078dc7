// The fused kernels (one spring pass and one update pass per tile row; vertical-only: one
// pass per pair of rows) against the row-pass kernels they replaced (KernelChoice::unfused,
// kept for this): the same bits after 1,000 steps with a violent disturbance, in both modes,
// dense and sleeping, for several tile sizes, with tiles of even and of odd row counts, in
// both compiled variants (AVX2 where the machine has it, and generic).

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <string>
#include <tuple>

#include "shore/water/surface.h"

using namespace shore::water;

namespace {

/// A 45 x ny basin (not a multiple of any tile) at 5 cm, 0.5 m deep, damped in 0.5 s so
/// tiles settle and sleep; the sleeping cases have open edges (the sponge's path). ny 52:
/// every tile has an even number of rows; 45: the last tiles an odd one (13 or 45), whose
/// last row the vertical-only kernel updates alone.
SurfaceSettings basin(SurfaceMode mode, int tile, bool sleep, KernelChoice kernel, int ny) {
  PhysicalParameters p;
  p.cell = 0.05;
  p.depth = 0.5;
  p.damping_time = 0.5;
  SurfaceSettings s = SurfaceSettings::physical(p, 45, ny);
  s.mode = mode;
  s.boundary = sleep ? Boundary::open : Boundary::vertical_only;
  s.open.width = 6;
  s.sleep.enabled = sleep;
  s.sleep.tile = tile;
  s.threads = 1;
  s.kernel = kernel;
  return s;
}

void island_and_drops(Surface& s) {
  for (int j = 30; j < 34; ++j)
    for (int i = 20; i < 23; ++i) s.set_fixed(i, j, true);
  s.set_constraint(12, 40, NodeConstraint::vertical_only);
  s.disturb(Disturbance::point_height(s.node_x(15), s.node_y(20), 0.1, 3.0));  // violent: 60 h, substeps
  s.disturb(Disturbance::point_velocity(s.node_x(30), s.node_y(12), 0.1, 0.5));
}

using Case = std::tuple<SurfaceMode, int, bool, int>;  // mode, tile, sleeping, rows

class FusedKernel : public ::testing::TestWithParam<Case> {};

TEST_P(FusedKernel, GivesTheUnfusedKernelsBitsAfter1000ViolentSteps) {
  const auto [mode, tile, sleep, rows] = GetParam();
  Surface fused(basin(mode, tile, sleep, KernelChoice::automatic, rows));
  Surface generic(basin(mode, tile, sleep, KernelChoice::generic, rows));
  Surface unfused(basin(mode, tile, sleep, KernelChoice::unfused, rows));
  ASSERT_STREQ(unfused.kernel_isa(), "unfused");
  const double rest_bound = fused.omega_bound();
  island_and_drops(fused);
  island_and_drops(generic);
  island_and_drops(unfused);
  const std::int64_t tiles = fused.tile_stats().tiles;
  std::int64_t fewest_awake = tiles;
  double highest_bound = 0.0;
  for (int k = 0; k < 1000; ++k) {
    highest_bound = std::max(highest_bound, fused.step(1.0 / 240).omega_bound);
    generic.step(1.0 / 240);
    unfused.step(1.0 / 240);
    fewest_awake = std::min(fewest_awake, fused.tile_stats().awake);
  }
  if (mode == SurfaceMode::full_3d) {
    EXPECT_GT(highest_bound, 1.1 * rest_bound);  // violent: the stretched lattice stiffened
  }
  if (sleep && tile == 16 && (rows == 52 || mode == SurfaceMode::vertical_only)) {
    EXPECT_LT(fewest_awake, tiles);  // tiles slept (and woke: the disturbances are spread)
  }
  const DenseState a = fused.dense_state(), b = unfused.dense_state();
  std::size_t differing = 0;
  const auto same = [](double x, double y) {
    return std::bit_cast<std::uint64_t>(x) == std::bit_cast<std::uint64_t>(y);
  };
  for (std::size_t k = 0; k < a.uz.size(); ++k) {
    differing += !same(a.uz[k], b.uz[k]) || !same(a.vz[k], b.vz[k]);
    if (mode == SurfaceMode::full_3d)
      differing +=
          !same(a.ux[k], b.ux[k]) || !same(a.uy[k], b.uy[k]) || !same(a.vx[k], b.vx[k]) || !same(a.vy[k], b.vy[k]);
  }
  EXPECT_EQ(differing, 0u) << "nodes that differ in any bit";
  EXPECT_EQ(fused.state_hash(), unfused.state_hash());
  EXPECT_EQ(generic.state_hash(), unfused.state_hash());
  EXPECT_EQ(fused.tile_stats().awake, unfused.tile_stats().awake);
  EXPECT_EQ(fused.omega_bound(), unfused.omega_bound());
}

INSTANTIATE_TEST_SUITE_P(ModesTilesSleeping, FusedKernel,
                         ::testing::Combine(::testing::Values(SurfaceMode::vertical_only, SurfaceMode::full_3d),
                                            ::testing::Values(16, 32, 128), ::testing::Bool(),
                                            ::testing::Values(52, 45)),
                         [](const ::testing::TestParamInfo<Case>& c) {
                           return std::string(std::get<0>(c.param) == SurfaceMode::full_3d ? "Full3d"
                                                                                           : "VerticalOnly") +
                                  "Tile" + std::to_string(std::get<1>(c.param)) +
                                  (std::get<2>(c.param) ? "Sleeping" : "Dense") + "Rows" +
                                  std::to_string(std::get<3>(c.param));
                         });

// Tiles one node wide and one node high (a 33 x 17 grid in tiles of 16: the last column
// and row of tiles), where the fused spring pass has no slot of its own and every spring
// is an edge slot, and tiles of 8.
TEST(FusedKernelThinTiles, GiveTheUnfusedKernelsBits) {
  for (const SurfaceMode mode : {SurfaceMode::vertical_only, SurfaceMode::full_3d}) {
    for (const int tile : {8, 16}) {
      SurfaceSettings s = SurfaceSettings::paper();
      s.nx = 33;
      s.ny = 17;
      s.mode = mode;
      s.boundary = Boundary::vertical_only;
      s.sleep.tile = tile;
      s.threads = 1;
      Surface fused(s);
      s.kernel = KernelChoice::unfused;
      Surface unfused(s);
      for (Surface* surf : {&fused, &unfused}) {
        surf->disturb(Disturbance::point_height(31.0, 15.0, 1.5, 5.0));  // in the thin tiles' corner
        surf->disturb(Disturbance::point_velocity(10.0, 8.0, 2.0, 1.0));
      }
      for (int k = 0; k < 300; ++k) {
        fused.step(0.4);
        unfused.step(0.4);
      }
      EXPECT_EQ(fused.state_hash(), unfused.state_hash())
          << (mode == SurfaceMode::full_3d ? "3-D" : "vertical") << ", tiles of " << tile;
    }
  }
}

}  // namespace
