#pragma once
// A root of a function on a bracket, by regula falsi with the Illinois rule: the soil's
// bearing solve (the offset that carries a load) and a raycast wheel's spin (the spin at
// which the rim's shear balances the engine) both narrow their brackets with it.

#include <algorithm>
#include <cmath>

namespace shore {

/// [lo, hi], with g(lo) < 0 <= g(hi).
struct Bracket {
  double lo = 0.0, hi = 0.0;
};

/// Narrows `b` (g(b.lo) = g_lo < 0 <= g_hi = g(b.hi)) until it is at most `width` wide, in
/// 200 steps at most, evaluating g at `point(b, g_lo, g_hi)` (inside b) each step: the
/// point replaces the end on its side of the root, and an end that stays twice in a row
/// has its value halved (Illinois), so regula falsi never stalls on it. Returns the last
/// bracket: the caller takes the end (or the middle) its answer needs.
template <class G, class Point>
Bracket illinois_narrow_by(G&& g, Bracket b, double g_lo, double g_hi, double width, Point&& point) {
  int side = 0;  // -1: the low end moved last, +1: the high end, 0: neither yet
  for (int it = 0; it < 200 && b.hi - b.lo > width; ++it) {
    const double mid = point(b, g_lo, g_hi);
    const double g_mid = g(mid);
    if (g_mid < 0.0) {
      b.lo = mid, g_lo = g_mid;
      if (side == -1) g_hi *= 0.5;
      side = -1;
    } else {
      b.hi = mid, g_hi = g_mid;
      if (side == 1) g_lo *= 0.5;
      side = 1;
    }
  }
  return b;
}

/// illinois_narrow_by at the secant's root, or at the middle where the secant is not
/// inside (an infinite end), kept 1 % of the bracket from its ends so that it never crawls.
template <class G>
Bracket illinois_narrow(G&& g, Bracket b, double g_lo, double g_hi, double width) {
  return illinois_narrow_by(g, b, g_lo, g_hi, width, [](const Bracket& at, double lo, double hi) {
    double mid = 0.5 * (at.lo + at.hi);
    if (std::isfinite(hi)) {
      const double secant = at.lo - lo * (at.hi - at.lo) / (hi - lo);
      if (secant > at.lo && secant < at.hi) mid = secant;
    }
    return std::clamp(mid, at.lo + 0.01 * (at.hi - at.lo), at.hi - 0.01 * (at.hi - at.lo));
  });
}

}  // namespace shore
