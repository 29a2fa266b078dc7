#pragma once
// x^n for one fixed exponent n, many x: Bekker's z^n for every column a raycast wheel's
// bearing solve measures. det::pow costs about 265 instructions (a double-double log and
// exp); this about 40, with the same bits on every machine (only IEEE-754 +, -, *, and
// bit reads, in a fixed order; tables filled by det::pow).
//
// x = m 2^e with m in [1, 2): x^n = 2^(n e) m^n, 2^(n e) from a table over e, and
// m^n = k^n (1 + r)^n with k the nearest of 129 knots 1 + i/128, r = (m - k) / k
// (|r| <= 1/256), (1 + r)^n from its binomial series through r^6 (the next term is below
// 2e-19 for n in (0, 4]). Within a few units in the last place of det::pow (tests/core/
// test_det_power.cpp); x outside [2^-64, 2^64) or not normal goes to det::pow.

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

#include "shore/core/det_math.h"

namespace shore::det {

class FixedPower {
 public:
  static constexpr int kKnots = 128;  ///< knots per octave of m
  static constexpr int kMinExponent = -64;
  static constexpr int kMaxExponent = 63;

  FixedPower() : FixedPower(1.0) {}
  /// n finite (Bekker's exponent: the tests cover 0.1 to 4).
  explicit FixedPower(double n) : n_(n) {
    for (int e = kMinExponent; e <= kMaxExponent; ++e)
      octave_[static_cast<std::size_t>(e - kMinExponent)] = det::pow(std::ldexp(1.0, e), n);  // n e rounds
    for (int i = 0; i <= kKnots; ++i) {
      const double k = 1.0 + static_cast<double>(i) / kKnots;
      knot_[static_cast<std::size_t>(i)] = det::pow(k, n);
      inverse_[static_cast<std::size_t>(i)] = 1.0 / k;
    }
    double c = 1.0;  // C(n, j), built up term by term
    for (int j = 1; j <= kTerms; ++j) {
      c = c * (n - (j - 1)) / j;
      binomial_[static_cast<std::size_t>(j)] = c;
    }
  }

  [[nodiscard]] double exponent() const noexcept { return n_; }

  /// x^n for x >= 0 (as det::pow(x, n) for any other x).
  [[nodiscard]] double operator()(double x) const {
    const std::uint64_t bits = std::bit_cast<std::uint64_t>(x);
    const int e = static_cast<int>((bits >> 52) & 0x7ff) - 1023;  // x >= 0 normal: x = m 2^e
    if ((bits >> 63) != 0 || e < kMinExponent || e > kMaxExponent) return det::pow(x, n_);
    const std::uint64_t fraction = bits & ((std::uint64_t{1} << 52) - 1);
    const double m = std::bit_cast<double>(fraction | (std::uint64_t{1023} << 52));
    // The nearest knot i / 128 of the fraction (ties up), from its top bits; k = 1 + i/128.
    const auto i = static_cast<std::size_t>((fraction + (std::uint64_t{1} << 44)) >> 45);
    const double k = 1.0 + static_cast<double>(i) * (1.0 / kKnots);  // exact
    const double r = (m - k) * inverse_[i];                          // m - k exact (Sterbenz)
    const double* c = binomial_.data();
    const double s = c[1] + r * (c[2] + r * (c[3] + r * (c[4] + r * (c[5] + r * c[6]))));
    const double rn = r * s;  // (1 + r)^n - 1
    return octave_[static_cast<std::size_t>(e - kMinExponent)] * (knot_[i] + knot_[i] * rn);
  }

 private:
  static constexpr int kTerms = 6;  ///< binomial series through r^6
  double n_ = 1.0;
  std::array<double, kMaxExponent - kMinExponent + 1> octave_{};  ///< 2^(n e)
  std::array<double, kKnots + 1> knot_{};                         ///< (1 + i/128)^n
  std::array<double, kKnots + 1> inverse_{};                      ///< 1 / (1 + i/128)
  std::array<double, kTerms + 1> binomial_{};                     ///< C(n, j)
};

}  // namespace shore::det
