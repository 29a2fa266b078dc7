// The slope box's reference (scenes/sliding_block.h): a rigid block sliding on
// Janosi-Hanamoto soil, checked against quadrature over the base, Wong's closed form for a
// track at full slip, Coulomb's block and the energy balance of a block that stops.
#include "shore/scenes/sliding_block.h"

#include <gtest/gtest.h>

#include <cmath>

#include "shore/core/error.h"

namespace {

using shore::scenes::mobilised_share;
using shore::scenes::SlidingBlock;

/// The share by quadrature over the base: soil x behind the front edge has been sheared by
/// min(x, slid) (it entered under the edge, or lay under the block from the start).
double share_by_quadrature(double slid, double length, double K) {
  constexpr int kSlices = 200000;
  double sum = 0.0;
  for (int q = 0; q < kSlices; ++q) {
    const double x = (q + 0.5) * length / kSlices;
    sum += 1.0 - std::exp(-std::fmin(x, slid) / K);
  }
  return sum / kSlices;
}

TEST(SlidingBlock, ShareIsJanosiHanamotoIntegratedOverTheBase) {
  for (const double K : {0.005, 0.012, 0.05})
    for (const double slid : {0.0, 0.002, 0.01, 0.1, 0.29, 0.3, 0.5})
      EXPECT_NEAR(mobilised_share(slid, 0.3, K), share_by_quadrature(slid, 0.3, K), 1e-6) << "K " << K << ", " << slid;
  EXPECT_EQ(mobilised_share(0.1, 0.3, 0.0), 1.0);  // Coulomb's block
}

TEST(SlidingBlock, SteadySlideMeetsWongsTrackAtFullSlipAndCoulombWithoutK) {
  SlidingBlock b;
  b.drive = 6.0, b.strength = 4.8, b.length = 0.3, b.seconds = 1.5;
  b.shear_modulus = 0.012;
  const double wong = b.drive - b.strength * (1.0 - 0.012 / 0.3 * (1.0 - std::exp(-0.3 / 0.012)));
  const auto steady = shore::scenes::slide(b);
  EXPECT_NEAR(steady.second_half, wong, 1e-3 * wong);
  // From rest the block first slides on soil it has barely sheared: faster than steady.
  EXPECT_GT(steady.whole, wong * 1.05);
  b.shear_modulus = 0.0;
  const auto coulomb = shore::scenes::slide(b);
  EXPECT_NEAR(coulomb.second_half, 1.2, 1e-3);
  EXPECT_NEAR(coulomb.whole, 1.2, 1e-3);
}

TEST(SlidingBlock, AHeldBlockCreepsUntilTheSoilHasTakenItsWork) {
  // Coulomb holds it (drive below strength); on the soil's curve it creeps from rest and
  // stops where the soil's shear has taken the work the drive did: int (drive - strength
  // share) ds = 0, with the share still rising.
  SlidingBlock b;
  b.drive = 3.0, b.strength = 4.8, b.length = 0.3, b.shear_modulus = 0.01;
  const auto m = shore::scenes::slide(b);
  ASSERT_GT(m.distance, 0.0);
  EXPECT_LT(m.distance, 0.1);
  EXPECT_EQ(m.second_half, 0.0);
  double work = 0.0;
  constexpr int kSlices = 100000;
  for (int q = 0; q < kSlices; ++q)
    work +=
        (b.drive - b.strength * mobilised_share((q + 0.5) * m.distance / kSlices, 0.3, 0.01)) * m.distance / kSlices;
  EXPECT_NEAR(work, 0.0, 1e-3 * b.drive * m.distance);
}

/// The pressure's centre ahead of the middle of a base of `length` tilted on Bekker soil of
/// exponent n, its sinkage z0 + x t at x from the middle (x ahead), by quadrature.
double pressure_centre(double n, double length, double z0, double t) {
  constexpr int kSlices = 200000;
  double load = 0.0, moment = 0.0;
  for (int q = 0; q < kSlices; ++q) {
    const double x = (q + 0.5) * length / kSlices - length / 2;
    const double p = std::pow(std::fmax(z0 + x * t, 0.0), n);
    load += p, moment += p * x;
  }
  return moment / load;
}

TEST(SlidingBlock, BekkersSoilCarriesAnEccentricityUpToTheBaseTiltedOntoItsRearEdge) {
  for (const double n : {0.13, 0.2, 0.5, 0.7, 1.1}) {
    const double limit = shore::scenes::bearing_eccentricity_limit(n, 0.3);
    // Tilted so that the rear edge just touches: the limit.
    EXPECT_NEAR(pressure_centre(n, 0.3, 0.15, 1.0), limit, 1e-6) << "n " << n;
    // Any tilt with the whole base bearing moves the centre less.
    for (const double rear_depth : {0.1, 0.5, 2.0})
      EXPECT_LT(pressure_centre(n, 0.3, 0.15 + rear_depth, 1.0), limit) << "n " << n << ", rear " << rear_depth;
  }
  // The softer the growth of pressure with depth, the less the base can carry.
  EXPECT_LT(shore::scenes::bearing_eccentricity_limit(0.13, 0.3), shore::scenes::bearing_eccentricity_limit(1.1, 0.3));
  EXPECT_DOUBLE_EQ(shore::scenes::base_eccentricity(0.8, 0.06), 0.024);  // the couple 0.8 N x 0.03 m over N
}

TEST(SlidingBlock, BadInputNamesTheField) {
  SlidingBlock b;
  b.length = 0.0;
  EXPECT_THROW((void)shore::scenes::slide(b), shore::InvalidSetting);
  b.length = 0.3, b.shear_modulus = -1.0;
  EXPECT_THROW((void)shore::scenes::slide(b), shore::InvalidSetting);
}

}  // namespace
