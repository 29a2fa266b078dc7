// FixedPower against det::pow (itself within an ulp of the C library's pow) and the C
// library's pow, over the sinkages and Bekker exponents Shore meets and past its tables.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

#include "shore/core/det_power.h"

namespace {

double ulps(double got, double want) {
  if (got == want) return 0.0;
  const double unit = std::ldexp(1.0, std::ilogb(std::max(std::fabs(want), std::numeric_limits<double>::min())) - 52);
  return std::fabs(got - want) / unit;
}

}  // namespace

TEST(FixedPower, WithinFourUlpsOfPowOverSinkagesAndExponents) {
  for (const double n : {0.1, 0.5, 0.7, 0.8, 1.0, 1.1, 1.6, 2.0, 3.3, 4.0}) {
    const shore::det::FixedPower power(n);
    double worst = 0.0, worst_libm = 0.0;
    std::uint64_t state = 12345;
    for (int k = 0; k < 20000; ++k) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      // log-uniform over [1e-9, 10] m: every mantissa and exponent of a sinkage
      const double x = std::exp(std::log(1e-9) + (std::log(10.0) - std::log(1e-9)) * double(state >> 11) * 0x1p-53);
      worst = std::max(worst, ulps(power(x), shore::det::pow(x, n)));
      worst_libm = std::max(worst_libm, ulps(power(x), std::pow(x, n)));
    }
    EXPECT_LE(worst, 4.0) << "n " << n;
    EXPECT_LE(worst_libm, 4.0) << "n " << n;
  }
}

TEST(FixedPower, KnotsOctaveEdgesAndOutsideTheTablesAreExactOrPows) {
  const shore::det::FixedPower power(1.1);
  EXPECT_EQ(power(1.0), 1.0);
  EXPECT_EQ(power(0.0), 0.0);
  EXPECT_EQ(power(2.0), shore::det::pow(2.0, 1.1));
  EXPECT_EQ(power(0.5), shore::det::pow(0.5, 1.1));
  for (const double x : {std::nextafter(2.0, 0.0), std::nextafter(1.0, 2.0), 1.0 + 1.0 / 256, 1.0 + 3.0 / 256})
    EXPECT_LE(ulps(power(x), std::pow(x, 1.1)), 4.0) << x;
  for (const double x : {1e-30, 1e30, 5e-324, -1.0, std::numeric_limits<double>::infinity()})  // det::pow's
    EXPECT_TRUE(std::isnan(x < 0 ? power(x) : 0.0) || power(x) == shore::det::pow(x, 1.1)) << x;
  EXPECT_DOUBLE_EQ(power.exponent(), 1.1);
}
