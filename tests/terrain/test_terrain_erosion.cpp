// A steep pile relaxes to the angle of repose; erosion conserves volume.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>

#include "shore/core/envelope.h"
#include "shore/terrain/terrain.h"
#include "terrain_fixtures.h"

using namespace shore::terrain;
using shore::terrain::testing::box_envelope;

namespace {

// Steepest slope (rad) between 8-neighbours over a square of columns.
double steepest_slope(const Terrain& t, std::int64_t lo, std::int64_t hi) {
  double steepest = 0.0;
  const double cell = t.settings().cell;
  for (std::int64_t j = lo; j < hi; ++j)
    for (std::int64_t i = lo; i < hi; ++i)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          if (!di && !dj) continue;
          const double dist = cell * std::hypot(di, dj);
          steepest = std::max(steepest, std::atan((t.height(i, j) - t.height(i + di, j + dj)) / dist));
        }
  return steepest;
}

}  // namespace

TEST(Erosion, SteepSandPileRelaxesToReposeAngle) {
  TerrainSettings s;
  s.material = Material::sand();
  s.max_erosion_passes = 1000;
  Terrain t(s);
  // A 60 degree cone, 10 cm radius.
  const double r = 0.10, slope = std::numbers::pi / 3;
  for (std::int64_t j = -12; j <= 12; ++j)
    for (std::int64_t i = -12; i <= 12; ++i) {
      const double d = std::hypot(t.column_x(i), t.column_y(j));
      if (d < r) t.set_height(i, j, (r - d) * std::tan(slope));
    }
  const double before = t.volume().ground;
  EXPECT_GT(before, 0.0);
  EXPECT_NEAR(t.volume().edited, before, 1e-15);
  EXPECT_GT(steepest_slope(t, -14, 14), 1.0);
  const shore::GridRect region{-40, -40, 80, 80};
  int rounds = 0;
  while (t.relax(region).erosion_passes == s.max_erosion_passes && rounds < 200) ++rounds;
  ASSERT_LT(rounds, 200);
  const double one_degree = std::numbers::pi / 180;
  EXPECT_LE(steepest_slope(t, -39, 39), s.material.theta_out + one_degree);
  EXPECT_NEAR(t.volume().ground, before, 1e-12 * before);
  // Settled at the repose angle, not far below it: the pile is still there.
  EXPECT_GT(steepest_slope(t, -39, 39), s.material.theta_out - 5 * one_degree);
  EXPECT_GT(t.height(0, 0), 0.05);
}

TEST(Erosion, SnowHoldsItsShape) {
  // theta_out = 1.57: snow walls stand (Sumner Table 1).
  TerrainSettings s;
  s.material = Material::snow();
  Terrain t(s);
  for (std::int64_t j = -3; j <= 3; ++j)
    for (std::int64_t i = -3; i <= 3; ++i) t.set_height(i, j, 0.05);
  const std::uint64_t h = t.state_hash();
  EXPECT_EQ(t.relax({-10, -10, 20, 20}).erosion_passes, 0);
  EXPECT_EQ(t.state_hash(), h);
}

// The pass cap limits the flow rate, it does not freeze slopes: a sphere pressed once
// into sand with a low cap leaves a rim that keeps eroding in later steps without any
// body, until it rests at the repose angle; then steps cost nothing.
TEST(Erosion, ErosionStoppedByTheCapCarriesOnWithoutABody) {
  TerrainSettings s;
  s.material = Material::sand();
  s.material.alpha = 1.0;  // everything into the rim
  s.max_erosion_passes = 2;
  Terrain t(s);
  const double r = 0.1, z = 0.05;
  shore::EnvelopeRaster env;
  env.resize(-12, -12, 25, 25, false);
  for (std::int64_t j = -12; j <= 12; ++j)
    for (std::int64_t i = -12; i <= 12; ++i) {
      const double d2 = t.column_x(i) * t.column_x(i) + t.column_y(j) * t.column_y(j);
      if (d2 < r * r) env.lower[env.index(i, j)] = -z + r - std::sqrt(r * r - d2);
    }
  const Imprint im{&env};
  ASSERT_EQ(t.step({&im, 1}).erosion_passes, 2);  // stopped by the cap
  const double volume = t.volume().ground;
  EXPECT_GT(steepest_slope(t, -14, 14), s.material.theta_out + 0.1);
  int steps = 0;
  StepReport report;
  do {
    report = t.step({});
    ++steps;
  } while (report.active_columns > 0 && steps < 2000);
  ASSERT_LT(steps, 2000);
  EXPECT_GT(steps, 2);
  const double one_degree = std::numbers::pi / 180;
  // Outside the crater (under the sphere, contact columns were held at their pressed depth).
  EXPECT_LE(steepest_slope(t, -30, 30), s.material.theta_stop + one_degree);
  EXPECT_NEAR(t.volume().ground, volume, 1e-12);
  EXPECT_EQ(t.step({}).active_columns, 0);
}

namespace {

// Mud (theta_in 90 degrees, theta_out and theta_stop 63) with a 10 x 10 column box pressed
// 3 cm in: vertical walls where the print meets its rim.
struct PressedMud {
  Terrain t;
  shore::EnvelopeRaster box = box_envelope(-5, -5, 10, 10, -0.03);
  double volume = 0.0;
  explicit PressedMud(TerrainSettings s) : t((s.material = Material::mud(), s)) {
    const Imprint press{&box};
    t.step({&press, 1});
    volume = t.volume().ground;
  }
  /// Steps until nothing is active (at most 500 steps); returns the steps taken.
  int settle(std::span<const Imprint> imprints) {
    int steps = 0;
    while (t.step(imprints).active_columns > 0 && steps < 500) ++steps;
    return steps;
  }
};

constexpr double kOneDegree = std::numbers::pi / 180;

}  // namespace

// A body that has lifted away supports no soil: once it is more than active_reach above
// its print, the print's vertical walls slump to the repose angle (theta_out). With an
// infinite reach the hovering body would hold them vertical forever.
TEST(Erosion, ALiftedBodyNoLongerHoldsItsPrintsWalls) {
  for (const double reach : {TerrainSettings{}.active_reach, std::numeric_limits<double>::infinity()}) {
    SCOPED_TRACE(reach);
    TerrainSettings s;
    s.active_reach = reach;
    s.max_erosion_passes = 64;  // the rim settles while the body presses: nothing is carried
    PressedMud mud(s);
    ASSERT_GT(steepest_slope(mud.t, -10, 10), 80 * kOneDegree);
    const shore::EnvelopeRaster lifted = box_envelope(-5, -5, 10, 10, 0.4);
    const Imprint hover{&lifted};
    for (int k = 0; k < 100; ++k) mud.t.step({&hover, 1});
    if (std::isinf(reach)) {
      EXPECT_GT(steepest_slope(mud.t, -10, 10), 80 * kOneDegree);
    } else {
      EXPECT_LE(steepest_slope(mud.t, -10, 10), mud.t.settings().material.theta_out + kOneDegree);
      EXPECT_LT(mud.settle({&hover, 1}), 500);
    }
    EXPECT_NEAR(mud.t.volume().ground, mud.volume, 1e-12);
  }
}

// A body taken away altogether leaves its print to erode: the step after it goes erodes
// what it reached as open ground, and the walls slump to the repose angle.
TEST(Erosion, ARemovedBodyLeavesItsPrintToErode) {
  TerrainSettings s;
  s.max_erosion_passes = 64;  // the rim settles while the body presses: nothing is carried
  PressedMud mud(s);
  const int steps = mud.settle({});
  EXPECT_GT(steps, 0);
  EXPECT_LT(steps, 500);
  EXPECT_LE(steepest_slope(mud.t, -10, 10), mud.t.settings().material.theta_out + kOneDegree);
  EXPECT_NEAR(mud.t.volume().ground, mud.volume, 1e-12);
}

// A body at rest is imprinted as holding: it presses nothing and starts no work...
TEST(Erosion, AHoldingImprintPressesNothingAndStartsNoWork) {
  Terrain t{TerrainSettings{}};
  const shore::EnvelopeRaster box = box_envelope(-5, -5, 10, 10, -0.03);
  Imprint hold{&box};
  hold.hold = true;
  const std::uint64_t before = t.state_hash();
  EXPECT_EQ(t.step({&hold, 1}).active_columns, 0);
  EXPECT_EQ(t.state_hash(), before);
}

// ...but where slopes next to it still erode, it keeps the soil out of its print: the
// columns it touches neither give nor receive. Without it the rim slides into the print.
TEST(Erosion, AHoldingImprintKeepsSlidingSoilOutOfItsPrint) {
  TerrainSettings s;
  s.max_erosion_passes = 1;  // the rim keeps eroding for many steps
  for (const bool held : {true, false}) {
    SCOPED_TRACE(held);
    PressedMud mud(s);
    Imprint hold{&mud.box};
    hold.hold = true;
    const int steps = held ? mud.settle({&hold, 1}) : mud.settle({});
    EXPECT_GT(steps, 1);
    EXPECT_LT(steps, 500);
    double highest = -1.0;
    for (std::int64_t j = -5; j < 5; ++j)
      for (std::int64_t i = -5; i < 5; ++i) highest = std::max(highest, mud.t.height(i, j));
    if (held)
      EXPECT_EQ(highest, -0.03);
    else
      EXPECT_GT(highest, -0.03 + 1e-3);
    EXPECT_NEAR(mud.t.volume().ground, mud.volume, 1e-12);
  }
}

// Erosion ends where slopes are within the stop tolerance, whatever else shares the active
// region: a 35 degree sand cone (between theta_out and theta_stop) erodes for one pass and
// stops, bit for bit the same whether or not a steep 70 degree cone 30 columns away keeps
// the region's passes going.
TEST(Erosion, ASlopeStopsCreepingWhateverElseSharesItsRegion) {
  TerrainSettings s;
  s.active_margin = 20;  // one region around the rod below holds both cones
  auto cone = [](Terrain& t, std::int64_t ci, std::int64_t cj, double degrees) {
    const double r = 0.08, tan_slope = std::tan(degrees * std::numbers::pi / 180);
    for (std::int64_t j = cj - 9; j <= cj + 9; ++j)
      for (std::int64_t i = ci - 9; i <= ci + 9; ++i) {
        const double d = std::hypot(t.column_x(i - ci), t.column_y(j - cj));
        if (d < r) t.set_height(i, j, (r - d) * tan_slope);
      }
  };
  // A thin rod 2 cm above the flat ground along row 0, within active_reach: it makes the
  // region and presses nothing.
  shore::EnvelopeRaster rod;
  rod.resize(-40, 0, 81, 1, false);
  for (double& v : rod.lower) v = 0.02;
  const Imprint hover{&rod};
  Terrain alone(s), shared(s);
  cone(alone, 25, 10, 35);
  cone(shared, 25, 10, 35);
  cone(shared, -25, 10, 70);
  const double apex = alone.height(25, 10);
  ASSERT_EQ(alone.step({&hover, 1}).erosion_passes, 1);
  EXPECT_LT(alone.height(25, 10), apex);  // the cone did erode
  ASSERT_EQ(shared.step({&hover, 1}).erosion_passes, s.max_erosion_passes);
  for (std::int64_t j = 0; j <= 20; ++j)
    for (std::int64_t i = 14; i <= 36; ++i) EXPECT_EQ(shared.height(i, j), alone.height(i, j)) << i << ", " << j;
}
