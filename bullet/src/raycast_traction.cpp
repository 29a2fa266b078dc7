#include "raycast_traction.h"

#include <algorithm>
#include <cmath>

#include "shore/core/det_math.h"
#include "shore/core/illinois.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

namespace {

constexpr double kSpinTolerance = 0x1p-40;  // the spin to this fraction of its range, as 40 bisections

/// The rim in the direction the wheel rolls: angles and speeds mirrored when it rolls back.
struct RollingFrame {
  double dir = 1.0;    ///< +1 rolling along the heading, -1 against it
  double entry = 0.0;  ///< rad, theta_1 in this frame
  double speed = 0.0;  ///< m/s, forward speed in this frame
  double sin_entry = 0.0;
};

struct RimForce {
  double along = 0.0;   ///< N, the shear along the rim (its sum: the torque over r)
  double thrust = 0.0;  ///< N, its horizontal part along the heading
  double side = 0.0;    ///< N along the axle
};

/// The rim's shear at spin `omega` (rad/s, in the rolling frame).
RimForce rim_force(std::span<const RimStrip> rim, const TractionInput& in, const RollingFrame& f, double omega) {
  const double r = in.radius;
  const double scale = std::max({std::fabs(omega) * r, std::fabs(f.speed), kTractionSpeedFloor});
  const double inv_k = 1.0 / in.shear_modulus, inv_l = 1.0 / in.remould_length;
  RimForce out;
  for (const RimStrip& s : rim) {
    const double theta = std::min(f.dir * s.theta, f.entry);  // in the rolling frame
    const double sin_theta = std::min(f.dir * s.sin_theta, f.sin_entry);
    const double arc = r * (f.entry - theta);  // rim passed since the strip's soil met it
    const double jx = (omega * r * arc - f.speed * r * (f.sin_entry - sin_theta)) / scale;
    const double jy = in.side_speed * arc / scale;  // how far the wheel slid sideways meanwhile
    const double j = std::sqrt(jx * jx + jy * jy);
    if (!(j > 0.0)) continue;
    const double kept = 1.0 - in.remould_shear_ratio * (1.0 - det::exp(-j * inv_l));
    const double tau = s.strength * kept * (1.0 - det::exp(-j * inv_k)) / j;
    out.along += tau * jx;
    out.thrust += tau * jx * s.cos_theta;
    out.side -= tau * jy;
  }
  return out;
}

// A warm search's first step from the last substep's spin, as a share of the spin's
// range, and how much longer each further step is while the root is not bracketed: a
// substep's change of spin is mostly well within the first.
constexpr double kWarmStep = 0x1p-10;
constexpr double kWarmGrowth = 8.0;

/// The bracket around the root of g (growing with the spin) from `guess` in (0, top):
/// steps away from it in the direction of the root, each kWarmGrowth times the last, until
/// g changes sign or the step reaches 0 or `top` (where the cold search's ends answer:
/// locked or spinning). `end` is set when the answer is such an end.
Bracket warm_bracket(const auto& g, double guess, double top, double& g_lo, double& g_hi, bool& end, double& at) {
  end = false;
  const double g_guess = g(guess);
  Bracket b{guess, guess};
  double step = kWarmStep * top;
  if (g_guess < 0.0) {  // the root lies above
    b.lo = guess, g_lo = g_guess;
    for (;; step *= kWarmGrowth) {
      const double o = std::min(b.lo + step, top), go = g(o);
      if (!(go < 0.0)) return b.hi = o, g_hi = go, b;
      if (o >= top) return end = true, at = top, b;  // spins: more than the soil takes
      b.lo = o, g_lo = go;
    }
  }
  b.hi = guess, g_hi = g_guess;
  for (;; step *= kWarmGrowth) {
    const double o = std::max(b.hi - step, 0.0), go = g(o);
    if (go < 0.0) return b.lo = o, g_lo = go, b;
    if (o <= 0.0) return end = true, at = 0.0, b;  // locked: the brake holds it
    b.hi = o, g_hi = go;
  }
}

/// Narrows `b` (g(b.lo) = g_lo < 0 <= g_hi = g(b.hi)) to at most `width` as illinois_narrow
/// does (the secant's root; an end kept twice in a row has its value halved), but where
/// the secant's root lies within 1 % of the bracket from an end, the point taken is twice as
/// far from that end (at least half the width): near the root, regula falsi lands ever
/// closer to the end that moves, and illinois_narrow's point 1 % in from it narrows the
/// bracket by a hundredth a step; twice the secant's distance lands past the root when the
/// secant has found it, and the bracket closes to that distance at once (Brent's rule). The
/// rim's shear is smooth down to some 1e-6 N: there the steps bisect, as illinois_narrow's.
Bracket narrow_spin(const auto& g, Bracket b, double g_lo, double g_hi, double width) {
  return illinois_narrow_by(g, b, g_lo, g_hi, width, [width](const Bracket& at, double lo, double hi) {
    const double w = at.hi - at.lo;
    double mid = at.lo - lo * w / (hi - lo);
    if (hi == 0.0)
      mid = at.hi;  // the root is the upper end: half a width below it closes the bracket
    else if (!(mid > at.lo && mid < at.hi))
      mid = 0.5 * (at.lo + at.hi);
    const double near = 0.01 * w;
    if (mid - at.lo < near) mid = at.lo + std::max(2.0 * (mid - at.lo), 0.5 * width);
    if (at.hi - mid < near) mid = at.hi - std::max(2.0 * (at.hi - mid), 0.5 * width);
    return mid;
  });
}

/// The spin of a wheel held at rest by the rim's shear and its brake in the rolling frame
/// (the balance at spin 0 lies forward of the root): locked, unless a drive against the
/// motion (a car rolling back, driven forward) overcomes the shear and the brake (which now
/// resists turning backward): then it turns against the motion, at most `top` fast.
double against_motion(const auto& along, double drive, double brake, double top) {
  const double target = drive + brake;  // turning backward, the brake helps the shear
  if (!(target < 0.0)) return 0.0;      // locked: the brake holds it
  const auto g = [&](double omega) { return along(omega) - target; };
  const double g_hi = g(0.0);
  if (!(g_hi > 0.0)) return 0.0;  // the shear and the brake hold it
  const double g_lo = g(-top);
  if (g_lo >= 0.0) return -top;  // spins backward: more than the soil takes
  const Bracket b = narrow_spin(g, Bracket{-top, 0.0}, g_lo, g_hi, kSpinTolerance * top);
  return 0.5 * (b.lo + b.hi);
}

/// The spin at which the rim's shear balances the drive less the brake (rolling frame).
double balancing_spin(std::span<const RimStrip> rim, const TractionInput& in, const RollingFrame& f) {
  const double drive = f.dir * in.drive, brake = std::max(in.brake, 0.0);
  const auto along = [&](double omega) { return rim_force(rim, in, f, omega).along; };
  const auto g = [&](double omega) { return along(omega) - (drive - brake); };
  const double top = (5.0 * std::max(f.speed, 0.0) + 2.0) / in.radius;
  const double guess = f.dir * in.last_spin;
  Bracket b;
  double g_lo = 0.0, g_hi = 0.0;
  if (guess > 0.0 && guess < top) {  // NaN (no last spin) fails both
    bool end = false;
    double at = 0.0;
    b = warm_bracket(g, guess, top, g_lo, g_hi, end, at);
    if (end) return at > 0.0 ? at : against_motion(along, drive, brake, top);
  } else {
    g_lo = g(0.0);
    if (g_lo >= 0.0) return against_motion(along, drive, brake, top);
    g_hi = g(top);
    if (g_hi <= 0.0) return top;  // spins: more than the soil takes
    b = {0.0, top};
  }
  // Some seven evaluations where bisection took forty to the same width; the middle of the
  // last bracket.
  b = narrow_spin(g, b, g_lo, g_hi, kSpinTolerance * top);
  return 0.5 * (b.lo + b.hi);
}

double slip_of(double omega, double speed, double r) {
  const double rim = omega * r;
  if (rim < 0.0 && speed > 0.0) return 1.0;  // turning against the motion: driven, slipping fully
  if (rim >= speed) return rim > 0.0 ? 1.0 - std::max(speed, 0.0) / rim : 0.0;  // driving
  return speed > 0.0 ? rim / speed - 1.0 : 0.0;                                 // braking
}

}  // namespace

double RimShear::at(double theta) const {
  const double th = std::min(dir * theta, entry);  // in the rolling frame, as rim_force
  const double arc = radius * (entry - th);
  const double jx = rim * arc - ground * radius * (sin_entry - det::sin(th)), jy = side * arc;
  return std::sqrt(jx * jx + jy * jy);
}

Traction soil_traction(std::span<const RimStrip> rim, const TractionInput& in) {
  RollingFrame f;
  if (in.hold)
    f.dir = in.held_spin * in.radius + in.forward_speed >= 0.0 ? 1.0 : -1.0;
  else if (std::fabs(in.forward_speed) > 1e-3)
    f.dir = in.forward_speed > 0.0 ? 1.0 : -1.0;
  else
    f.dir = in.drive < 0.0 ? -1.0 : 1.0;
  f.entry = f.dir > 0.0 ? in.entry_angle : -in.exit_angle;
  f.sin_entry = det::sin(f.entry);
  f.speed = f.dir * in.forward_speed;
  const double omega = in.hold ? f.dir * in.held_spin : balancing_spin(rim, in, f);
  const RimForce force = rim_force(rim, in, f, omega);
  Traction t;
  t.spin = f.dir * omega;
  t.slip = slip_of(omega, f.speed, in.radius);
  t.forward = f.dir * force.thrust;
  t.side = force.side;
  t.torque = f.dir * force.along * in.radius;
  const double scale = std::max({std::fabs(omega) * in.radius, std::fabs(f.speed), kTractionSpeedFloor});
  t.shear = RimShear{
      f.dir, in.radius, f.entry, f.sin_entry, omega * in.radius / scale, f.speed / scale, in.side_speed / scale};
  return t;
}

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
