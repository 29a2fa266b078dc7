// shore::det against the C library (an outside reference, to a few units in the last
// place) and against identities; plus pinned bit patterns, which fail if a build fuses
// multiplies and adds or otherwise rounds differently.

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "shore/core/det_math.h"

namespace {

/// Distance in units in the last place of the larger magnitude.
double ulps(double got, double want) {
  if (got == want) return 0.0;
  const double unit = std::ldexp(1.0, std::ilogb(std::max(std::fabs(want), std::numeric_limits<double>::min())) - 52);
  return std::fabs(got - want) / unit;
}

template <class F, class G>
double worst_ulps(F mine, G libm, double lo, double hi, int samples) {
  double worst = 0.0;
  for (int k = 0; k <= samples; ++k) {
    const double x = lo + (hi - lo) * k / samples;
    worst = std::max(worst, ulps(mine(x), libm(x)));
  }
  return worst;
}

TEST(DetMath, ExpAndLogAgreeWithTheCLibraryWithinOneUlp) {
  // The C library's exp and log are within an ulp of the exact value, and so are these
  // (at most 0.503 ulp against 50-digit decimal arithmetic over 15,000 random points when
  // the table method went in), so the two differ by at most one ulp.
  EXPECT_LE(worst_ulps(
                shore::det::exp, [](double x) { return std::exp(x); }, -700.0, 700.0, 20011),
            1.0);
  EXPECT_LE(worst_ulps(
                shore::det::exp, [](double x) { return std::exp(x); }, -1.0, 1.0, 20011),
            1.0);
  EXPECT_LE(worst_ulps(
                shore::det::log, [](double x) { return std::log(x); }, 1e-300, 1e-290, 2001),
            1.0);
  EXPECT_LE(worst_ulps(
                shore::det::log, [](double x) { return std::log(x); }, 1e-6, 10.0, 20011),
            1.0);
  EXPECT_LE(worst_ulps(
                shore::det::log, [](double x) { return std::log(x); }, 0.5, 2.0, 20011),
            1.0);
}

TEST(DetMath, PowAgreesWithTheCLibraryOverBekkersRange) {
  // Bekker: z^n with z from micrometres to a metre, n from 0.3 to 2; and its inverse.
  double worst = 0.0;
  for (double n : {0.3, 0.7, 1.1, 1.6, 2.0, 1.0 / 1.1, 2.0 / 3.2})
    for (int k = 0; k <= 4000; ++k) {
      const double z = 1e-6 * std::pow(1e6, k / 4000.0);
      worst = std::max(worst, ulps(shore::det::pow(z, n), std::pow(z, n)));
    }
  EXPECT_LE(worst, 1.0);
  EXPECT_EQ(shore::det::pow(0.0, 1.1), 0.0);
  EXPECT_EQ(shore::det::pow(0.0, 0.0), 1.0);
  EXPECT_EQ(shore::det::pow(3.0, 0.0), 1.0);
  EXPECT_TRUE(std::isnan(shore::det::pow(-1.0, 0.5)));
  EXPECT_EQ(shore::det::pow(4.0, 0.5), 2.0);
}

TEST(DetMath, TrigonometryAgreesWithTheCLibrary) {
  const double pi = 3.14159265358979323846;
  EXPECT_LE(worst_ulps(
                shore::det::sin, [](double x) { return std::sin(x); }, -10.0, 10.0, 20011),
            4.0);
  EXPECT_LE(worst_ulps(
                shore::det::cos, [](double x) { return std::cos(x); }, -10.0, 10.0, 20011),
            4.0);
  // Near zeros of sin and cos the relative error of the reduction grows: compare absolutely.
  for (int k = -6; k <= 6; ++k) {
    EXPECT_NEAR(shore::det::sin(k * pi), 0.0, 1e-15 * (1 + std::abs(k)));
    EXPECT_NEAR(shore::det::cos(k * pi + pi / 2), 0.0, 1e-15 * (1 + std::abs(k)));
  }
  // Material angles: [0, pi/2), tan up to ~1e3.
  EXPECT_LE(worst_ulps(
                shore::det::tan, [](double x) { return std::tan(x); }, 0.0, 1.5699, 20011),
            4.0);
  EXPECT_LE(worst_ulps(
                shore::det::atan, [](double x) { return std::atan(x); }, -50.0, 50.0, 20011),
            4.0);
  for (double y : {-2.0, -0.5, 0.0, 0.3, 1.0})
    for (double x : {-3.0, -1.0, -0.2, 0.2, 1.0, 4.0}) {
      EXPECT_LE(ulps(shore::det::atan2(y, x), std::atan2(y, x)), 4.0) << y << " " << x;
    }
  EXPECT_EQ(shore::det::atan2(0.0, -1.0), std::atan2(0.0, -1.0));
}

TEST(DetMath, ErfAgreesWithTheCLibraryAbsolutely) {
  double worst = 0.0;
  for (int k = -8000; k <= 8000; ++k) {
    const double x = k * 1e-3;
    worst = std::max(worst, std::fabs(shore::det::erf(x) - std::erf(x)));
  }
  EXPECT_LT(worst, 2e-15);  // a few ulps of 1
  EXPECT_EQ(shore::det::erf(0.0), 0.0);
  EXPECT_EQ(shore::det::erf(-0.7), -shore::det::erf(0.7));
}

TEST(DetMath, SpecialValues) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(shore::det::exp(0.0), 1.0);
  EXPECT_EQ(shore::det::exp(800.0), inf);
  EXPECT_EQ(shore::det::exp(-800.0), 0.0);
  EXPECT_TRUE(std::isnan(shore::det::exp(std::nan(""))));
  EXPECT_EQ(shore::det::log(1.0), 0.0);
  EXPECT_EQ(shore::det::log(0.0), -inf);
  EXPECT_TRUE(std::isnan(shore::det::log(-1.0)));
  EXPECT_EQ(shore::det::log(inf), inf);
}

TEST(DetMath, ScalingByPowersOfTwoMatchesLdexpAndFrexpAtTheRangeEdges) {
  // exp scales its polynomial by 2^k from the bits, and log reads the exponent from the
  // bits; both fall back to the C library's ldexp / frexp (exact operations) where the
  // result or argument is not a normal number. Both paths must give ldexp's exact bits.
  for (int k : {-1074, -1060, -1040, -1023, -1022, -1021, -1020, -1019, -1, 0, 1, 1019, 1020, 1021, 1023})
    for (double x : {0.70710678118654752, 1.0, 1.4142135623730951, 1.9999999999999998}) {
      SCOPED_TRACE(k);
      EXPECT_EQ(std::bit_cast<std::uint64_t>(shore::det::detail::times_power_of_two(x, k)),
                std::bit_cast<std::uint64_t>(std::ldexp(x, k)));
    }
  for (double x : {4.9e-324, 2.2250738585072009e-308, 2.2250738585072014e-308, 0.5, 1.0, 3.0, 1.7976931348623157e308}) {
    int e_det = 0, e_libc = 0;
    const double m_det = shore::det::detail::mantissa_exponent(x, e_det), m_libc = std::frexp(x, &e_libc);
    EXPECT_EQ(m_det, m_libc) << x;
    EXPECT_EQ(e_det, e_libc) << x;
  }
  // Near the subnormal edge exp stays within a few ulps of the C library too.
  for (double x = -745.0; x < -700.0; x += 0.37) {
    const double ours = shore::det::exp(x), libc = std::exp(x);
    EXPECT_LE(std::abs(ours - libc), 4 * std::abs(std::nextafter(libc, 0.0) - libc) + 5e-324) << x;
  }
}

std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

TEST(DetMath, PinnedBitsHoldOnEveryMachine) {
  // Values from the reference build. They change only if the arithmetic does: a compiler
  // contracting a * b + c into a fused multiply-add, or an edit of the polynomials.
  EXPECT_EQ(bits(shore::det::pow(0.0437, 1.1)), 0x3fa05c510f221f23ull);  // (a fused build gives ...24)
  EXPECT_EQ(bits(shore::det::exp(-1.234567)), 0x3fd29f19b75f99c4ull);
  EXPECT_EQ(bits(shore::det::log(0.0123)), 0xc01197b635f81342ull);
  EXPECT_EQ(bits(shore::det::tan(0.436)), 0x3fddd15b70bd972dull);
  EXPECT_EQ(bits(shore::det::sin(2.5)), 0x3fe326af0dcfcab0ull);
  EXPECT_EQ(bits(shore::det::atan2(0.3, -0.8)), 0x400643382c07913aull);
  EXPECT_EQ(bits(shore::det::erf(0.8)), 0x3fe7bf4a85b7fb84ull);
}

}  // namespace
