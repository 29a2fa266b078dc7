// Kinematic bodies pressed into flat ground leave imprints whose volume is the solid's.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "shore/terrain/terrain.h"
#include "terrain_fixtures.h"

using namespace shore::terrain;
using namespace shore::terrain::testing;

namespace {

TerrainSettings snow_settings(double alpha) {
  TerrainSettings s;
  s.material = Material::snow();
  s.material.alpha = alpha;
  return s;
}

// Presses a sphere of radius r from touching the ground to depth z in `steps` steps.
void press_sphere(Terrain& t, double r, double z, int steps, bool star = false) {
  for (int k = 1; k <= steps; ++k) {
    const double bottom = -z * k / steps;
    const shore::EnvelopeRaster env = sphere_envelope(t, 0.0, 0.0, bottom + r, r);
    const Imprint im{&env, 0.0, star};
    t.step({&im, 1});
  }
}

void press_box(Terrain& t, std::int64_t i0, std::int64_t j0, int nx, int ny, double z, int steps) {
  for (int k = 1; k <= steps; ++k) {
    const shore::EnvelopeRaster env = box_envelope(i0, j0, nx, ny, -z * k / steps);
    const Imprint im{&env};
    t.step({&im, 1});
  }
}

}  // namespace

TEST(Imprint, SphereInSnowAllCompressedMatchesCapVolume) {
  Terrain t(snow_settings(0.0));
  const double r = 0.1, z = 0.03;
  press_sphere(t, r, z, 10);
  const GroundChange g = ground_change(t, -20, -20, 41, 41);
  const double cap = cap_volume(r, z);
  EXPECT_NEAR(g.lowered, cap, 0.02 * cap);
  EXPECT_NEAR(g.raised, 0.0, 1e-12);
  const VolumeTotals v = t.volume();
  EXPECT_NEAR(v.compacted, g.lowered, 1e-12);  // all of it compressed
  EXPECT_NEAR(v.total(), 0.0, 1e-9 * cap);     // nothing lost
  EXPECT_NEAR(t.height(0, 0), -z, 1e-12);      // the deepest column sits at the sphere's bottom
  EXPECT_NEAR(t.sinkage(0, 0), z, 1e-12);
}

TEST(Imprint, SphereInSnowAllDisplacedRimHoldsTheCap) {
  Terrain t(snow_settings(1.0));
  const double r = 0.1, z = 0.03;
  press_sphere(t, r, z, 10);
  const GroundChange g = ground_change(t, -20, -20, 41, 41);
  const double cap = cap_volume(r, z);
  EXPECT_NEAR(g.raised, g.lowered, 1e-9 * cap);  // the rim holds what the pit lost
  EXPECT_NEAR(g.lowered, cap, 0.02 * cap);
  EXPECT_NEAR(t.volume().ground, 0.0, 1e-9 * cap);
  EXPECT_NEAR(t.volume().compacted, 0.0, 1e-15);
}

TEST(Imprint, BoxMatchesPrismVolume) {
  const double z = 0.02;
  const int nx = 20, ny = 12;  // 0.20 m x 0.12 m at 1 cm
  const double prism = nx * 0.01 * ny * 0.01 * z;
  {
    Terrain t(snow_settings(0.0));
    press_box(t, 0, 0, nx, ny, z, 8);
    const GroundChange g = ground_change(t, -10, -10, nx + 20, ny + 20);
    EXPECT_NEAR(g.lowered, prism, 0.02 * prism);
    EXPECT_NEAR(t.volume().compacted, prism, 0.02 * prism);
    EXPECT_NEAR(t.volume().total(), 0.0, 1e-9 * prism);
  }
  {
    Terrain t(snow_settings(1.0));
    press_box(t, 0, 0, nx, ny, z, 8);
    const GroundChange g = ground_change(t, -10, -10, nx + 20, ny + 20);
    EXPECT_NEAR(g.lowered, prism, 0.02 * prism);
    EXPECT_NEAR(g.raised, prism, 0.02 * prism);
    EXPECT_NEAR(t.volume().ground, 0.0, 1e-9 * prism);
  }
}

TEST(Imprint, SandRimErodesButKeepsVolume) {
  TerrainSettings s;
  s.material = Material::sand();
  s.material.alpha = 1.0;
  Terrain t(s);
  const double r = 0.1, z = 0.03;
  press_sphere(t, r, z, 10);
  const double cap = cap_volume(r, z);
  EXPECT_NEAR(t.volume().ground, 0.0, 1e-9 * cap);
  // The rim spread beyond the first ring: erosion moved material outward.
  const GroundChange g = ground_change(t, -20, -20, 41, 41);
  EXPECT_NEAR(g.raised, g.lowered, 1e-9 * cap);
}

TEST(Imprint, StarLowersNeighboursButSinkageFollowsTheTrueEnvelope) {
  Terrain t(snow_settings(0.0));
  const double r = 0.1, z = 0.03;
  press_sphere(t, r, z, 10, /*star=*/true);
  const shore::EnvelopeRaster env = sphere_envelope(t, 0.0, 0.0, -z + r, r);
  for (std::int64_t j = -12; j <= 12; ++j)
    for (std::int64_t i = -12; i <= 12; ++i) {
      // Lowest body point within +-1 column, by direct search over the analytic sphere.
      double lowest = 0.0;
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di)
          if (env.contains(i + di, j + dj)) lowest = std::min(lowest, env.lower[env.index(i + di, j + dj)]);
      EXPECT_LE(t.height(i, j), lowest + 1e-12) << i << "," << j;
      const double true_depth = env.contains(i, j) ? std::max(0.0, -env.lower[env.index(i, j)]) : 0.0;
      EXPECT_LE(t.sinkage(i, j), true_depth + 1e-12) << i << "," << j;
    }
  EXPECT_NEAR(t.sinkage(0, 0), z, 1e-12);
}

TEST(Imprint, ChangedRectanglesCoverExactlyTheChangedColumns) {
  TerrainSettings s;
  s.tile_columns = 16;  // several tiles under the sphere
  Terrain t(s);
  t.take_changed();
  std::vector<double> before;
  for (std::int64_t j = -20; j <= 20; ++j)
    for (std::int64_t i = -20; i <= 20; ++i) before.push_back(t.height(i, j));
  press_sphere(t, 0.1, 0.02, 1);
  const auto rects = t.take_changed();
  ASSERT_FALSE(rects.empty());
  std::size_t k = 0;
  for (std::int64_t j = -20; j <= 20; ++j)
    for (std::int64_t i = -20; i <= 20; ++i, ++k) {
      if (t.height(i, j) == before[k]) continue;
      bool inside = false;
      for (const auto& r : rects) inside = inside || (i >= r.i0 && i < r.i0 + r.nx && j >= r.j0 && j < r.j0 + r.ny);
      EXPECT_TRUE(inside) << i << "," << j;
    }
  for (const auto& r : rects) {  // tight: each rectangle's border rows and columns hold a change
    EXPECT_LE(r.nx, 16);
    EXPECT_LE(r.ny, 16);
  }
  EXPECT_TRUE(t.take_changed().empty());  // nothing changed since
}

// A large sphere pressed shallowly covers a wide window but touches a small patch: the
// active region follows the columns within active_reach of the soil (plus active_margin),
// and for pure compaction that changes no column at all.
TEST(Imprint, ActiveRegionFollowsTheSoilNotTheWholeBody) {
  const double r = 0.5, z = 0.01;
  auto press = [&](double reach) {
    TerrainSettings s = snow_settings(0.0);
    s.active_reach = reach;
    Terrain t(s);
    const shore::EnvelopeRaster env = sphere_envelope(t, 0.0, 0.0, -z + r, r);
    const Imprint im{&env};
    const StepReport report = t.step({&im, 1});
    return std::pair{report.active_columns, t.state_hash()};
  };
  const auto [all_columns, all_hash] = press(std::numeric_limits<double>::infinity());
  const double reach = 0.03, cell = TerrainSettings{}.cell;
  const auto [near_columns, near_hash] = press(reach);
  // Columns within the reach lie inside radius sqrt(2 r (z + reach)) of the bottom point.
  const int margin = TerrainSettings{}.active_margin;
  const int across = 2 * static_cast<int>(std::ceil(std::sqrt(2 * r * (z + reach)) / cell)) + 1 + 2 * margin;
  EXPECT_LE(near_columns, across * across);
  EXPECT_GE(all_columns, 100 * 100);  // the whole 1 m window
  EXPECT_EQ(near_hash, all_hash);
}

TEST(Imprint, BodyHighAboveTheSoilCostsNothingWithAFiniteReach) {
  TerrainSettings s = snow_settings(0.0);
  s.active_reach = 0.03;
  Terrain t(s);
  const shore::EnvelopeRaster env = sphere_envelope(t, 0.0, 0.0, 0.5, 0.1);  // bottom 0.4 m up
  const Imprint im{&env};
  EXPECT_EQ(t.step({&im, 1}).active_columns, 0);
  EXPECT_EQ(t.tile_count(), 0U);
}

// Displaced soil comes out from under the body: a column the body overhangs inside its
// contact patch (a 1 cm gap in its sole) is passed over, not filled. It used to collect
// the displaced soil of the whole patch around it and rise into the body.
TEST(Imprint, DisplacedSoilIsNotPiledIntoAGapInTheContactPatch) {
  Terrain t(snow_settings(1.0));  // everything displaced, nothing slumps
  shore::EnvelopeRaster sole = box_envelope(-5, -5, 11, 11, -0.02);
  sole.lower[sole.index(0, 0)] = 0.01;  // the gap: 1 cm above the ground, within active_reach
  const Imprint im{&sole};
  t.step({&im, 1});
  EXPECT_EQ(t.height(0, 0), 0.0);
  // All 120 pressed columns' soil lies in the ring around the sole.
  const GroundChange g = ground_change(t, -10, -10, 21, 21);
  const double cell2 = t.settings().cell * t.settings().cell;
  EXPECT_NEAR(g.lowered, 120 * 0.02 * cell2, 1e-12);
  EXPECT_NEAR(g.raised, g.lowered, 1e-12);
  double inside = 0.0;
  for (std::int64_t j = -5; j <= 5; ++j)
    for (std::int64_t i = -5; i <= 5; ++i) inside = std::max(inside, t.height(i, j));
  EXPECT_LE(inside, 0.0);
}
