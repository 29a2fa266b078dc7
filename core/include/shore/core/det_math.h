#pragma once
// Elementary functions with the same bits on every machine.
//
// The C library's exp, log, pow, sin, tan and erf are not specified to the last bit, and
// glibc picks a different implementation by CPU feature (an FMA variant where the CPU has
// FMA), so the same binary can round differently on two machines. Everything Shore
// computes into its state (Bekker's pressure, erosion thresholds, disturbance weights,
// spray) uses these instead: range reduction and polynomials made only of IEEE-754 basic
// operations (+, -, *, /, sqrt, floor, ldexp, frexp), which are exact or correctly rounded
// everywhere, evaluated in a fixed order. Shore builds them with -ffp-contract=off (see
// cmake/ShoreDeterminism.cmake) so no compiler fuses a multiply and an add.
//
// Accuracy: exp, log and pow within about half a unit in the last place of the exact value
// (table-driven, Tang's method; the tables are exact hexadecimal constants written by
// scripts/det_math_tables.py), so within one of the C library's; the others within a few
// units of the C library's over the ranges Shore uses (tests/core/test_det_math.cpp).
// exp costs about 80 instructions, pow about 265.

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "shore/core/det_math_tables.h"

namespace shore::det {

namespace detail {

inline constexpr double kLn2Hi = 6.93147180369123816490e-01;  // ln 2, high part (32 trailing zero bits)
inline constexpr double kLn2Lo = 1.90821492927058770002e-10;  // ln 2 - kLn2Hi
inline constexpr double kInvLn2 = 1.44269504088896338700e+00;
// pi / 2 in three parts; the first two have trailing zero bits, so k * part is exact for
// the |k| < 2^20 this file reduces.
inline constexpr double kPio2Hi = 1.57079632673412561417e+00;
inline constexpr double kPio2Mid = 6.07710050650619224932e-11;
inline constexpr double kPio2Lo = 2.02226624879595063154e-21;
inline constexpr double kPi = 3.14159265358979311600e+00;
inline constexpr double kHalfPi = 1.57079632679489655800e+00;
inline constexpr double kSixthPi = 5.23598775598298815658e-01;
inline constexpr double kSqrt3 = 1.73205080756887719318e+00;
inline constexpr double kTanTwelfthPi = 2.67949192431122695758e-01;  // tan(pi / 12)

inline constexpr double factorial(int n) { return n <= 1 ? 1.0 : n * factorial(n - 1); }

/// 1 / n! for n in [0, 18], computed by the compiler (correctly rounded divisions).
struct InverseFactorials {
  double v[19] = {};
  constexpr InverseFactorials() {
    for (int n = 0; n < 19; ++n) v[n] = 1.0 / factorial(n);
  }
};
inline constexpr InverseFactorials kInvFact{};

/// (-1)^(n+1) / n for n in [1, 10], the Taylor coefficients of ln(1 + r), by the compiler.
struct LogSeries {
  double v[11] = {};
  constexpr LogSeries() {
    for (int n = 1; n < 11; ++n) v[n] = ((n & 1) ? 1.0 : -1.0) / n;
  }
};
inline constexpr LogSeries kLogSeries{};

/// sin(r) for |r| <= pi/4: Taylor series through r^17 (next term < 1e-19).
inline double sin_kernel(double r) {
  const double z = r * r;
  double p = kInvFact.v[17];
  p = -kInvFact.v[15] + z * p;
  p = kInvFact.v[13] + z * p;
  p = -kInvFact.v[11] + z * p;
  p = kInvFact.v[9] + z * p;
  p = -kInvFact.v[7] + z * p;
  p = kInvFact.v[5] + z * p;
  p = -kInvFact.v[3] + z * p;
  return r + (r * z) * p;
}

/// cos(r) for |r| <= pi/4: Taylor series through r^18.
inline double cos_kernel(double r) {
  const double z = r * r;
  double p = -kInvFact.v[18];
  p = kInvFact.v[16] + z * p;
  p = -kInvFact.v[14] + z * p;
  p = kInvFact.v[12] + z * p;
  p = -kInvFact.v[10] + z * p;
  p = kInvFact.v[8] + z * p;
  p = -kInvFact.v[6] + z * p;
  p = kInvFact.v[4] + z * p;
  return (1.0 - 0.5 * z) + (z * z) * p;
}

/// x = quadrant * pi/2 + r, |r| <= pi/4 (Cody-Waite in three parts; exact enough for
/// |x| < 2^20, beyond which Shore has no angles).
inline double reduce_half_pi(double x, int& quadrant) {
  const double k = std::floor(x * (2.0 / kPi) + 0.5);
  quadrant = static_cast<int>(static_cast<long long>(k) & 3);
  return ((x - k * kPio2Hi) - k * kPio2Mid) - k * kPio2Lo;
}

/// atan(t) for |t| <= tan(pi/12): Taylor series t - t^3/3 + t^5/5 - ... through t^35
/// (next term < 1e-20), Horner from the top; term k has the sign (-1)^((k - 1) / 2).
inline double atan_kernel(double t) {
  const double z = t * t;
  double p = -1.0 / 35.0;
  for (int k = 33; k >= 3; k -= 2) p = ((k / 2) % 2 ? -1.0 : 1.0) / k + z * p;
  return t + (t * z) * p;
}

}  // namespace detail

namespace detail {

/// x 2^k, exactly as std::ldexp gives it (the product by a normal power of two is exact
/// unless it leaves the normal range), without a call into the C library in the common case.
inline double times_power_of_two(double x, int k) {
  if (k < -1020 || k > 1020) return std::ldexp(x, k);
  return x * std::bit_cast<double>(static_cast<std::uint64_t>(k + 1023) << 52);
}

/// std::frexp for x > 0 (m in [0.5, 1), x = m 2^e), read from the bits when x is normal.
inline double mantissa_exponent(double x, int& e) {
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(x);
  const int biased = static_cast<int>((bits >> 52) & 0x7ff);
  if (biased == 0 || biased == 0x7ff) return std::frexp(x, &e);  // subnormal, infinite or NaN
  e = biased - 1022;
  return std::bit_cast<double>((bits & ~(std::uint64_t{0x7ff} << 52)) | (std::uint64_t{1022} << 52));
}

/// a * b = p + err exactly (Dekker's product; needs -ffp-contract=off, which Shore builds with).
inline void two_product(double a, double b, double& p, double& err) {
  constexpr double kSplit = 134217729.0;  // 2^27 + 1
  const double ca = kSplit * a, cb = kSplit * b;
  const double ah = ca - (ca - a), al = a - ah;
  const double bh = cb - (cb - b), bl = b - bh;
  p = a * b;
  err = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
}

/// a + b = s + err exactly (Knuth's sum, any order of magnitudes).
inline void two_sum(double a, double b, double& s, double& err) {
  s = a + b;
  const double bb = s - a;
  err = (a - (s - bb)) + (b - bb);
}

/// e^(x + tail) for |tail| << 1 ulp of x's reduced argument (the low part of a product).
/// Tang's method: x = (64 k + j) ln2 / 64 + r, e^x = 2^k 2^(j/64) e^r, with 2^(j/64) from
/// a table (det_math_tables.h) and e^r - 1 from its Taylor series, |r| <= ln2 / 128.
inline double exp_with_tail(double x, double tail) {
  if (x != x) return x;
  if (x > 709.782712893384) return std::numeric_limits<double>::infinity();
  if (x < -745.1332191019412) return 0.0;
  // ln2 / 64 in two parts: the high part keeps kLn2Hi's 32 trailing zero bits, so n times
  // it is exact for |n| < 2^32.
  constexpr double kStepHi = kLn2Hi / 64, kStepLo = kLn2Lo / 64;
  // n = floor(x 64 / ln2 + 1/2), by truncation and a step down for negative fractions.
  const double nearest = x * (64 * kInvLn2) + 0.5;
  std::int64_t steps = static_cast<std::int64_t>(nearest);
  if (static_cast<double>(steps) > nearest) --steps;
  const auto n = static_cast<double>(steps);
  const double r = ((x - n * kStepHi) - n * kStepLo) + tail;
  const int j = static_cast<int>(steps & 63);
  const int k = static_cast<int>((steps - j) / 64);
  // e^r - 1 = r + r^2 (1/2 + r/6 + ... + r^5/7!): the next term is below 3e-20 of r.
  double q = kInvFact.v[7];
#pragma GCC unroll 5
  for (int m = 6; m >= 2; --m) q = kInvFact.v[m] + r * q;
  const double em1 = r + (r * r) * q;
  const HiLo& t = kExp2Table[j];
  const double e = t.hi + (t.hi * em1 + t.lo * (1.0 + em1));
  return times_power_of_two(e, k);
}

/// ln x = hi + lo for finite x > 0, the pair good to ~1e-19 absolute beyond hi's rounding.
/// x = m 2^e with m in [sqrt 1/2, sqrt 2); m is multiplied by a table's inv close to 1/m
/// (10 significant bits, so the product is exact as two doubles), leaving
/// ln x = e ln2 - ln(inv) + ln(1 + r), |r| < 0.0125, the last from its Taylor series.
inline void log_parts(double x, double& hi, double& lo) {
  int e = 0;
  double m = mantissa_exponent(x, e);  // x = m 2^e, m in [0.5, 1)
  if (m < 0.70710678118654752440) {
    m *= 2.0;
    --e;
  }
  const int i = static_cast<int>(m * 64.0 + 0.5);  // floor: positive
  const LogEntry& t = kLogTable[i - kLogTableFirst];
  double p = 0.0, p_err = 0.0;
  two_product(m, t.inv, p, p_err);
  const double r = p - 1.0;  // exact (p within 2 % of 1); r + p_err is m inv - 1 exactly
  // ln(1 + r) - r = r^2 (-1/2 + r/3 - r^2/4 + ... + r^8/10): the next term is below 1e-21 of r.
  double c = kLogSeries.v[10];
#pragma GCC unroll 8
  for (int n = 9; n >= 2; --n) c = kLogSeries.v[n] + r * c;
  const double tail = (r * r) * c;
  const double de = static_cast<double>(e);
  double s1 = 0.0, e1 = 0.0, s2 = 0.0, e2 = 0.0;
  two_sum(de * kLn2Hi, t.neg_ln, s1, e1);  // de * kLn2Hi is exact (32 trailing zero bits)
  two_sum(s1, r, s2, e2);
  // ln(1 + r + p_err) = ln(1 + r) + p_err / (1 + r), the quotient to first order in r.
  const double small = ((e1 + e2) + (t.neg_ln_lo + de * kLn2Lo)) + ((p_err - p_err * r) + tail);
  hi = s2 + small;
  lo = small - (hi - s2);  // |s2| >= |small| or s2 == 0
}

}  // namespace detail

/// e^x.
inline double exp(double x) { return detail::exp_with_tail(x, 0.0); }

/// Natural logarithm; NaN below zero, -infinity at zero.
inline double log(double x) {
  if (x != x || x < 0.0) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0.0) return -std::numeric_limits<double>::infinity();
  if (x == std::numeric_limits<double>::infinity()) return x;
  double hi = 0.0, lo = 0.0;
  detail::log_parts(x, hi, lo);
  return hi;
}

/// x^y for x >= 0 (NaN for x < 0 unless y == 0); 0^y is 0 for y > 0, 1 for y == 0.
/// exp(y ln x) with ln x and the product carried in two parts, so the result is good to a
/// few ulps however large y ln x is.
inline double pow(double x, double y) {
  if (y == 0.0 || x == 1.0) return 1.0;
  if (x != x || y != y) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0.0) return y > 0.0 ? 0.0 : std::numeric_limits<double>::infinity();
  if (x < 0.0) return std::numeric_limits<double>::quiet_NaN();
  if (x == std::numeric_limits<double>::infinity()) return y > 0.0 ? x : 0.0;
  double hi = 0.0, lo = 0.0;
  detail::log_parts(x, hi, lo);
  double p = 0.0, err = 0.0;
  detail::two_product(y, hi, p, err);
  if (!std::isfinite(p)) return p > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
  return detail::exp_with_tail(p, err + y * lo);
}

inline double sin(double x) {
  int q = 0;
  const double r = detail::reduce_half_pi(x, q);
  switch (q) {
    case 0:
      return detail::sin_kernel(r);
    case 1:
      return detail::cos_kernel(r);
    case 2:
      return -detail::sin_kernel(r);
    default:
      return -detail::cos_kernel(r);
  }
}

inline double cos(double x) {
  int q = 0;
  const double r = detail::reduce_half_pi(x, q);
  switch (q) {
    case 0:
      return detail::cos_kernel(r);
    case 1:
      return -detail::sin_kernel(r);
    case 2:
      return -detail::cos_kernel(r);
    default:
      return detail::sin_kernel(r);
  }
}

inline double tan(double x) {
  int q = 0;
  const double r = detail::reduce_half_pi(x, q);
  const double s = detail::sin_kernel(r), c = detail::cos_kernel(r);
  return (q & 1) ? -c / s : s / c;
}

/// atan(x) in [-pi/2, pi/2].
inline double atan(double x) {
  if (x != x) return x;
  const bool negative = x < 0.0;
  double t = negative ? -x : x;
  double base = 0.0;
  bool complement = false;
  if (t > 1.0) {  // atan t = pi/2 - atan(1/t)
    t = 1.0 / t;
    complement = true;
  }
  if (t > detail::kTanTwelfthPi) {  // atan t = pi/6 + atan((t sqrt3 - 1) / (t + sqrt3))
    t = (t * detail::kSqrt3 - 1.0) / (t + detail::kSqrt3);
    base = detail::kSixthPi;
  }
  double a = base + detail::atan_kernel(t);
  if (complement) a = detail::kHalfPi - a;
  return negative ? -a : a;
}

/// atan2(y, x) in [-pi, pi].
inline double atan2(double y, double x) {
  if (x != x || y != y) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0.0 && y == 0.0) return std::signbit(x) ? (std::signbit(y) ? -detail::kPi : detail::kPi) : y;
  if (std::fabs(x) >= std::fabs(y)) {
    const double a = det::atan(y / x);
    if (x > 0.0) return a;
    return std::signbit(y) ? a - detail::kPi : a + detail::kPi;
  }
  const double a = det::atan(x / y);
  return y > 0.0 ? detail::kHalfPi - a : -detail::kHalfPi - a;
}

/// Error function.
inline double erf(double x) {
  if (x != x) return x;
  const double ax = std::fabs(x);
  double value;
  if (ax < 2.5) {
    // erf x = 2/sqrt(pi) exp(-x^2) sum x (2 x^2)^n / (1 3 5 ... (2n + 1)): every term is
    // positive, so nothing is lost to cancellation (the alternating Taylor series lost
    // three digits near 2.5).
    const double z2 = 2.0 * ax * ax;
    double term = ax, sum = ax;
    for (int n = 1; n < 120; ++n) {
      term *= z2 / (2 * n + 1);
      sum += term;
      if (term < 1e-17 * sum) break;
    }
    value = sum * det::exp(-ax * ax) * 1.12837916709551257390;  // 2 / sqrt(pi)
  } else if (ax < 6.0) {
    // erfc x = exp(-x^2) / sqrt(pi) * K(x), K the continued fraction
    // 1 / (x + (1/2) / (x + 1 / (x + (3/2) / (x + 2 / (x + ...))))), evaluated bottom-up
    // with a fixed depth (ample for x >= 2.5).
    double f = ax;
    for (int k = 60; k >= 1; --k) f = ax + (0.5 * k) / f;
    value = 1.0 - det::exp(-ax * ax) * 0.56418958354775628695 / f;  // 1 / sqrt(pi)
  } else {
    value = 1.0;
  }
  return x < 0.0 ? -value : value;
}

}  // namespace shore::det
