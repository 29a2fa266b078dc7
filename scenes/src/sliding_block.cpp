#include "shore/scenes/sliding_block.h"

#include <cmath>
#include <cstdint>

#include "shore/core/error.h"

namespace shore::scenes {

double mobilised_share(double slid, double length, double shear_modulus) {
  if (shear_modulus <= 0.0) return 1.0;
  const double K = shear_modulus, s = std::fmax(slid, 0.0);
  if (s >= length) return 1.0 - K / length * (1.0 - std::exp(-length / K));
  const double old_soil = 1.0 - std::exp(-s / K);  // sheared by s, the whole time under the block
  return (s - K * old_soil + (length - s) * old_soil) / length;
}

double base_eccentricity(double shear_over_normal, double height) { return 0.5 * height * shear_over_normal; }

double bearing_eccentricity_limit(double n, double length) { return n * length / (2.0 * (n + 2.0)); }

SlidingBlockMotion slide(const SlidingBlock& b) {
  const Check check{"scenes.SlidingBlock"};
  check.finite("drive", b.drive);
  check.non_negative("strength", b.strength);
  check.positive("length", b.length);
  check.non_negative("shear_modulus", b.shear_modulus);
  check.positive("seconds", b.seconds);
  // Semi-implicit Euler at a step far below the time the block takes to slide K (the
  // share rises over the first few K); 150,000 steps for the matrix's 1.5 s.
  constexpr double kStep = 1e-5;
  const auto steps = static_cast<std::int64_t>(std::ceil(b.seconds / kStep));
  const double dt = b.seconds / double(steps);
  double s = 0.0, v = 0.0, v_half = 0.0;
  for (std::int64_t k = 0; k < steps; ++k) {
    const double a = b.drive - b.strength * mobilised_share(s, b.length, b.shear_modulus);
    // At rest, the soil holds whatever it can (static friction up to the mobilised strength).
    v = (v <= 0.0 && a <= 0.0) ? 0.0 : std::fmax(0.0, v + a * dt);
    s += v * dt;
    if (k + 1 == steps / 2) v_half = v;
  }
  SlidingBlockMotion out;
  out.distance = s;
  out.whole = 2.0 * s / (b.seconds * b.seconds);
  out.second_half = (v - v_half) / (b.seconds - dt * double(steps / 2));
  return out;
}

}  // namespace shore::scenes
