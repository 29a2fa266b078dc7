// A raycast wheel's balancing spin (raycast_traction.h) searched from the last substep's
// spin: the same root as the search over the whole range, to the search's width, from a
// start near the root or far from it on either side, and the ends (a braked wheel the soil
// cannot turn stays locked, a wheel asked for more than the soil takes spins at the top)
// answered as the whole range's search answers them.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "raycast_traction.h"

using namespace shore::bullet::coupling_detail;

namespace {

constexpr double kRadius = 0.4;

/// A rim in contact from 0.35 rad ahead of the bottom to 0.05 rad behind it, strips one
/// centimetre long, each carrying a share of a 4 kN load on dry sand.
std::vector<RimStrip> rim() {
  std::vector<RimStrip> strips;
  for (double s = -0.02; s <= 0.14; s += 0.01) {
    RimStrip r;
    r.theta = std::asin(s / kRadius);
    r.sin_theta = std::sin(r.theta), r.cos_theta = std::cos(r.theta);
    r.strength = 240.0 / r.cos_theta;
    strips.push_back(r);
  }
  return strips;
}

TractionInput driven(double drive, double brake) {
  TractionInput in;
  in.radius = kRadius;
  in.entry_angle = std::asin(0.145 / kRadius);
  in.exit_angle = std::asin(-0.025 / kRadius);
  in.shear_modulus = 0.01;
  in.remould_shear_ratio = 0.2;
  in.remould_length = 0.06;
  in.forward_speed = 1.5;
  in.side_speed = 0.1;
  in.drive = drive;
  in.brake = brake;
  return in;
}

double top_spin(const TractionInput& in) { return (5.0 * std::max(in.forward_speed, 0.0) + 2.0) / in.radius; }

}  // namespace

/// The balancing spin by bisection on held spins (a held wheel's torque is the rim's shear
/// at that spin), independent of the search's own narrowing.
double bisected_spin(const std::vector<RimStrip>& strips, TractionInput in) {
  const double target = in.drive - in.brake;
  double lo = 0.0, hi = top_spin(in);
  in.hold = true;
  for (int k = 0; k < 60; ++k) {
    in.held_spin = 0.5 * (lo + hi);
    (soil_traction(strips, in).torque / kRadius < target ? lo : hi) = in.held_spin;
  }
  return 0.5 * (lo + hi);
}

TEST(RaycastTraction, ASearchFromTheLastSpinFindsTheWholeRangesRoot) {
  const std::vector<RimStrip> strips = rim();
  for (const double drive : {-800.0, 150.0, 900.0, 2500.0}) {
    TractionInput in = driven(drive, drive < 0.0 ? 900.0 : 0.0);
    const Traction cold = soil_traction(strips, in);
    ASSERT_GT(cold.spin, 0.0) << drive;
    ASSERT_LT(cold.spin, top_spin(in)) << drive;
    // The rim's shear is smooth to some 1e-6 N: the roots agree to far below a slip's digits.
    EXPECT_NEAR(cold.spin, bisected_spin(strips, in), 1e-9 * top_spin(in)) << drive;
    // The search's width is 2^-40 of the range; both answers lie within it of the root.
    const double width = 0x1p-39 * top_spin(in);
    for (const double start : {1e-6, 0.5, 0.97, 1.0, 1.003, 1.5, 3.0}) {
      in.last_spin = std::min(start * cold.spin, 0.999 * top_spin(in));
      const Traction warm = soil_traction(strips, in);
      EXPECT_NEAR(warm.spin, cold.spin, width) << "drive " << drive << ", from " << in.last_spin;
      EXPECT_NEAR(warm.forward, cold.forward, 1e-6 * std::abs(cold.forward) + 1e-9) << drive;
      EXPECT_NEAR(warm.torque, cold.torque, 1e-6 * std::abs(cold.torque) + 1e-9) << drive;
    }
  }
}

TEST(RaycastTraction, ASearchFromTheLastSpinAnswersTheEndsAsTheWholeRange) {
  const std::vector<RimStrip> strips = rim();
  // Braked harder than the soil can turn it: locked, from any start.
  TractionInput locked = driven(0.0, 5000.0);
  ASSERT_EQ(soil_traction(strips, locked).spin, 0.0);
  for (const double start : {0.01, 1.0, 10.0}) {
    locked.last_spin = start;
    EXPECT_EQ(soil_traction(strips, locked).spin, 0.0) << start;
  }
  // Driven harder than the soil takes: the top of the range, from any start.
  TractionInput spinning = driven(20000.0, 0.0);
  const double top = top_spin(spinning);
  ASSERT_EQ(soil_traction(strips, spinning).spin, top);
  for (const double start : {0.01, 0.5 * top, 0.999 * top}) {
    spinning.last_spin = start;
    EXPECT_EQ(soil_traction(strips, spinning).spin, top) << start;
  }
  // No last spin (NaN), a start outside the range, or one rolling the other way: the whole
  // range's search, the same answer to the bit.
  TractionInput in = driven(900.0, 0.0);
  const double cold = soil_traction(strips, in).spin;
  for (const double start : {std::numeric_limits<double>::quiet_NaN(), 0.0, -3.0, 2.0 * top}) {
    in.last_spin = start;
    EXPECT_EQ(soil_traction(strips, in).spin, cold) << start;
  }
}

// A wheel rolling back (a car rocking in a hole, or pushed) while its engine drives it
// forward. Driven below what the soil holds, it keeps turning back, slower than it rolls,
// and its shear balances the drive (the wheel has no inertia of its own). Driven beyond it,
// it turns forward against the motion, at the top of the range, and the soil's whole shear
// pushes the chassis forward; held locked instead, a wheel the soil cannot hold would skid
// and stop the car it should drive.
TEST(RaycastTraction, AWheelDrivenAgainstTheMotionTurnsAgainstItPastTheSoilsHold) {
  const std::vector<RimStrip> strips = rim();
  double strength = 0.0;  // what the rim's soil holds at most: every strip's strength
  for (const RimStrip& s : strips) strength += s.strength;
  TractionInput in = driven(0.0, 0.0);
  in.forward_speed = -0.5, in.side_speed = 0.0;
  const double rolling = in.forward_speed / kRadius;
  in.drive = 0.2 * strength;
  const Traction held = soil_traction(strips, in);
  EXPECT_LT(held.spin, 0.0) << "rad/s: still turning back";
  EXPECT_GT(held.spin, rolling) << "rad/s: slower than it rolls";
  EXPECT_NEAR(held.torque / kRadius, in.drive, 1e-6 * in.drive) << "N: the shear balances the drive";
  EXPECT_GT(held.forward, 0.0) << "N: pushed forward";
  in.drive = 1.5 * strength;
  const Traction spun = soil_traction(strips, in);
  // The range's top in the backward-rolling frame: (5 |v| + 2) / r.
  EXPECT_EQ(spun.spin, (5.0 * 0.5 + 2.0) / kRadius) << "rad/s: forward, the top of the range";
  EXPECT_GT(spun.forward, 0.5 * strength) << "N: the soil's shear, forward";
  EXPECT_LE(spun.forward, strength) << "N";
  EXPECT_EQ(spun.slip, 1.0) << "driven, slipping fully";
}
