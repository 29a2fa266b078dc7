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

/// One Illinois step's bookkeeping: `mid` (with g(mid) = g_mid) replaces the end of `b` on
/// its side of the root; an end kept twice in a row (`side`: -1 the low end moved last, +1
/// the high end, 0 neither yet) has its value halved, so regula falsi never stalls on it.
inline void illinois_keep(Bracket& b, double& g_lo, double& g_hi, int& side, double mid, double g_mid) {
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

/// Narrows `b` (g(b.lo) = g_lo < 0 <= g_hi = g(b.hi)) until it is at most `width` wide, in
/// 200 steps at most. Each step evaluates g at the secant's root, or at the middle where the
/// secant is not inside (an infinite end), kept 1 % of the bracket from its ends so that it
/// never crawls; an end that stays twice in a row has its value halved (Illinois). Returns
/// the last bracket: the caller takes the end (or the middle) its answer needs.
template <class G>
Bracket illinois_narrow(G&& g, Bracket b, double g_lo, double g_hi, double width) {
  int side = 0;
  for (int it = 0; it < 200 && b.hi - b.lo > width; ++it) {
    double mid = 0.5 * (b.lo + b.hi);
    if (std::isfinite(g_hi)) {
      const double secant = b.lo - g_lo * (b.hi - b.lo) / (g_hi - g_lo);
      if (secant > b.lo && secant < b.hi) mid = secant;
    }
    mid = std::clamp(mid, b.lo + 0.01 * (b.hi - b.lo), b.hi - 0.01 * (b.hi - b.lo));
    illinois_keep(b, g_lo, g_hi, side, mid, g(mid));
  }
  return b;
}

}  // namespace shore
