// Volume conservation over long walks, and bit-identical results for any thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "shore/terrain/terrain.h"
#include "terrain_fixtures.h"

using namespace shore::terrain;
using namespace shore::terrain::testing;

namespace {

// Two small feet walking along x: each footfall presses 5 substeps down to 1.5 cm, then
// lifts for 5 substeps; the feet alternate and advance 6 cm a stride.
void walk(Terrain& t, int substeps, double& abs_disturbed) {
  const double cell = t.settings().cell;
  for (int s = 0; s < substeps; ++s) {
    const int fall = s / 10, phase = s % 10;
    const double depth = phase < 5 ? 0.015 * (phase + 1) / 5 : 0.015 * (10 - phase) / 5 - 0.02;
    const double x = 0.06 * fall;
    const double y = (fall % 2) ? 0.05 : -0.05;
    const std::int64_t i0 = t.column_i(x), j0 = t.column_j(y);
    const shore::EnvelopeRaster env = box_envelope(i0, j0, static_cast<int>(0.06 / cell), static_cast<int>(0.04 / cell),
                                                   -depth + 0.02 * (fall % 3) * 0.1);
    const Imprint im{&env};
    abs_disturbed += t.step({&im, 1}).displaced_volume;
  }
}

}  // namespace

TEST(Volume, WalkingFeetConserveVolumeEveryMaterial) {
  for (const Material& m : {Material::sand(), Material::mud(), Material::snow(), Material::rigid_ground()}) {
    TerrainSettings s;
    s.cell = 0.02;
    s.material = m;
    s.max_erosion_passes = 16;
    Terrain t(s);
    double displaced = 0.0;
    walk(t, 10000, displaced);
    const VolumeTotals v = t.volume();
    if (m.rigid) {
      EXPECT_EQ(displaced, 0.0);
      EXPECT_EQ(v.total(), 0.0);
      continue;
    }
    // Reference scale: the volume currently moved away from the untouched ground.
    double moved = 0.0;
    const double a = s.cell * s.cell;
    for (std::int64_t j = -20; j <= 20; ++j)
      for (std::int64_t i = -20; i <= 100; ++i) moved += std::abs(t.height(i, j) - t.base_height(i, j)) * a;
    ASSERT_GT(moved, 0.0) << m.name;
    EXPECT_LE(std::abs(v.total()), 1e-6 * moved) << m.name << ": total " << v.total() << " vs moved " << moved;
    EXPECT_GT(displaced, 0.0);
  }
}

namespace {

// A sphere rolling and a star-imprinted box pressing beside it, on sand with erosion.
std::uint64_t run_with_threads(int threads, int substeps) {
  TerrainSettings s;
  s.material = Material::sand();
  s.material.alpha = 0.6;
  s.threads = threads;
  s.parallel_min_columns = 0;  // split even this small region between threads
  s.max_erosion_passes = 4;    // fewer fork-joins: this machine's cores are shared
  s.tile_columns = 32;
  Terrain t(s);
  for (int k = 0; k < substeps; ++k) {
    const double x = 0.002 * k;
    const shore::EnvelopeRaster ball = sphere_envelope(t, x, 0.0, 0.07 - 0.02 - 0.00002 * k, 0.07);
    const shore::EnvelopeRaster box = box_envelope(t.column_i(0.2 - x), 12, 6, 4, -0.01 - 0.00004 * k);
    const Imprint ims[2] = {{&ball, 0.0, false}, {&box, 0.001, true}};
    t.step(ims);
  }
  return t.state_hash();
}

}  // namespace

TEST(Threads, SameStateHashForOneTwoAndFourThreads) {
  const int substeps = 500;
  const std::uint64_t one = run_with_threads(1, substeps);
  EXPECT_EQ(run_with_threads(2, substeps), one);
  EXPECT_EQ(run_with_threads(4, substeps), one);
  // Settings.threads = 0: the machine's thread count (no environment variable).
  EXPECT_EQ(run_with_threads(0, 50), run_with_threads(1, 50));
}

TEST(Memory, OneSquareMetreOfAKilometreFieldAllocatesOnlyItsTiles) {
  TerrainSettings s;  // 1 cm columns, 64-column tiles
  s.origin_x = -500.0, s.origin_y = -500.0;
  s.base = std::make_shared<LatticeNoise>(LatticeNoiseSettings{});
  Terrain t(s);  // a 1 km x 1 km field: 10^10 columns, none stored
  EXPECT_EQ(t.tile_count(), 0u);
  const std::size_t empty = t.memory_bytes();
  EXPECT_LT(empty, 64u * 1024u);
  // A 1 m x 1 m plate pressed in the middle of the field.
  const std::int64_t i0 = t.column_i(0.0), j0 = t.column_j(0.0);
  const shore::EnvelopeRaster plate = box_envelope(i0, j0, 100, 100, -0.05);
  const Imprint im{&plate};
  t.step({&im, 1});
  EXPECT_LT(t.height(i0 + 50, j0 + 50), t.base_height(i0 + 50, j0 + 50));
  // The region (100 + 2 margin + 2 halo columns a side) spans at most 3 tiles a side.
  const std::size_t max_tiles = 3 * 3;
  EXPECT_LE(t.tile_count(), max_tiles);
  EXPECT_GE(t.tile_count(), 4u);
  const std::size_t per_tile = 3 * sizeof(double) * 64 * 64;
  EXPECT_LT(t.memory_bytes(), empty + max_tiles * per_tile + 2u * 1024u * 1024u);
  // Far away the ground is untouched and unstored.
  EXPECT_EQ(t.height(t.column_i(400.0), t.column_j(-400.0)),
            s.base->height(t.column_x(t.column_i(400.0)), t.column_y(t.column_j(-400.0))));
  EXPECT_LE(t.tile_count(), max_tiles);
}
