// Exact volume in a closed pool, and no energy from round-off in the undamped 3-D lattice.
// References: a closed pool (vertical-only walls, no fixed nodes) keeps its water, so the
// sum of the heights is a constant of the motion; the time-centred energy of the undamped
// linear lattice is exactly conserved by the scheme (surface.h), so any drift at small
// amplitude is round-off. The 100,000-step runs are in the benchmark (water sweep,
// water.volume_drift_100k); these shorter runs fail on the float state (its volume drifted
// by 1e-2 of the bump within 5,000 steps, its 3-D energy rose by 1 % within 20,000).

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "shore/water/surface.h"

using namespace shore::water;

namespace {

SurfaceSettings pool(SurfaceMode mode, bool sleep, int threads) {
  PhysicalParameters p;
  p.cell = 0.05;
  p.depth = 0.5;
  p.damping_time = 2.0;
  SurfaceSettings s = SurfaceSettings::physical(p, 65, 65);
  s.mode = mode;
  s.boundary = Boundary::vertical_only;  // walls: a closed pool
  s.sleep.enabled = sleep;
  s.threads = threads;
  s.parallel_min_nodes = 0;
  return s;
}

struct VolumeCase {
  SurfaceMode mode;
  bool sleep;
  int threads;
};

class ClosedPool : public ::testing::TestWithParam<VolumeCase> {};

TEST_P(ClosedPool, KeepsItsVolumeToTheLastBit) {
  const VolumeCase c = GetParam();
  Surface s(pool(c.mode, c.sleep, c.threads));
  // A 1 cm bump off centre, and a kick of zero net vertical momentum (equal and opposite
  // at two nodes): the pool must keep its water.
  s.disturb(Disturbance::point_height(s.node_x(20), s.node_y(27), 0.15, 0.01));
  ASSERT_TRUE(s.add_vertical_velocity(45, 40, 0.05));
  ASSERT_TRUE(s.add_vertical_velocity(45, 44, -0.05));
  const double v0 = s.volume();
  const double bump = 0.01 * 2.0 * 3.14159265358979 * 0.15 * 0.15;  // m^3, the bump's volume
  ASSERT_NEAR(v0, bump, 0.02 * bump);
  double worst = 0.0;
  for (int k = 0; k < 5000; ++k) {
    s.step(1.0 / 240);
    worst = std::max(worst, std::abs(s.volume() - v0));
  }
  EXPECT_LE(worst / bump, 1e-9) << "drift " << worst << " m^3 of a " << bump << " m^3 bump";
  EXPECT_EQ(s.volume(), v0) << "not exact to the last bit";
  EXPECT_NEAR(s.mean_level(), v0 / (65.0 * 65.0 * 0.05 * 0.05), 1e-15);
  RecordProperty("volume_drift_rel", std::to_string(worst / bump));
}

INSTANTIATE_TEST_SUITE_P(Modes, ClosedPool,
                         ::testing::Values(VolumeCase{SurfaceMode::vertical_only, false, 1},
                                           VolumeCase{SurfaceMode::vertical_only, true, 2},
                                           VolumeCase{SurfaceMode::full_3d, false, 1},
                                           VolumeCase{SurfaceMode::full_3d, true, 2}),
                         [](const ::testing::TestParamInfo<VolumeCase>& c) {
                           return std::string(c.param.mode == SurfaceMode::full_3d ? "Full3d" : "VerticalOnly") +
                                  (c.param.sleep ? "_Sleeping" : "_Dense");
                         });

TEST(ClosedPool, VolumeChangesByExactlyWhatIsAdded) {
  Surface s(pool(SurfaceMode::vertical_only, true, 1));
  const double h = s.spacing();
  // Edits are rounded to the height quantum (about 2^-38 h); the volume is their exact sum.
  ASSERT_TRUE(s.add_height(30, 30, 0.004));
  EXPECT_NEAR(s.volume(), 0.004 * h * h, 1e-11 * h * h * h);  // within a quantum
  const double after_one = s.volume();
  const std::vector<double> dz = {0.001, -0.002, 0.003, 0.0005};
  const double added = s.add_heights(10, 10, 2, 2, dz);
  EXPECT_NEAR(added, 0.0025 * h * h, 4e-11 * h * h * h);
  EXPECT_EQ(s.volume(), after_one + added);
  EXPECT_DOUBLE_EQ(s.mean_level(), s.settings().rest_height + s.volume() / (65.0 * 65.0 * h * h));
  s.step(1.0 / 240);
  EXPECT_EQ(s.volume(), after_one + added);
}

// The undamped 3-D lattice at 0.003 h (0.15 mm): its time-centred energy must not grow.
// The float kernel's pre-tension forces (c (h - L0) per spring, cancelling at every node)
// carried a round-off independent of the amplitude, which heated small waves by about
// 2e-11 J per step.
TEST(UndampedLattice, SmallWavesGainNoEnergyFromRoundOff) {
  PhysicalParameters p;
  p.cell = 0.05;
  p.depth = 0.5;
  p.damping_time = std::numeric_limits<double>::infinity();
  SurfaceSettings set = SurfaceSettings::physical(p, 65, 65);
  set.mode = SurfaceMode::full_3d;
  set.boundary = Boundary::fixed;
  set.sleep.enabled = false;
  set.threads = 1;
  Surface s(set);
  s.disturb(Disturbance::point_height(s.node_x(0) + 1.18, s.node_y(0) + 1.31, 0.15, 0.003 * p.cell));
  s.step(1.0 / 240);
  const double e0 = s.energy().centred;
  ASSERT_GT(e0, 0.0);
  double worst = 0.0;
  for (int k = 1; k <= 20000; ++k) {
    s.step(1.0 / 240);
    if (k % 2000 == 0) worst = std::max(worst, s.energy().centred / e0 - 1.0);
  }
  EXPECT_LT(worst, 1e-4) << "relative energy gain";
  RecordProperty("energy_gain_rel", std::to_string(worst));
}

}  // namespace
