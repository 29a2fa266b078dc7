#pragma once
// A rigid block released at rest on a slope of Janosi-Hanamoto soil: the reference the
// validation matrix's slope boxes are measured against.
//
// Coulomb's block takes the base's full strength c A + N tan(phi) at once. On soil whose
// shear stress is (c + sigma tan(phi)) (1 - exp(-j / K)) a sliding block carries that
// strength only where the soil under it has been sheared by a few K: soil that entered
// under the front edge x behind it has j = x (Wong's track at full slip), and the soil
// under the block when it was released has j = s, the distance slid. Integrated over a
// base of length L under uniform pressure, the share of the full strength the base carries
// after sliding s is
//   s < L:  [s - K (1 - exp(-s / K)) + (L - s) (1 - exp(-s / K))] / L
//   s >= L: 1 - (K / L) (1 - exp(-L / K))   (Wong's tractive effort of a track at slip 1)
// rising from 0 at rest. K = 0 is Coulomb's block.

namespace shore::scenes {

struct SlidingBlock {
  double drive = 0.0;          ///< m/s^2, g sin(theta) less any other resistance per unit mass; finite
  double strength = 0.0;       ///< m/s^2, the base's full shear strength (c A + N tan(phi)) per unit mass; >= 0
  double length = 0.3;         ///< m, the base's length along the slope; > 0
  double shear_modulus = 0.0;  ///< m, Janosi-Hanamoto's K; >= 0 (0: Coulomb's block)
  double seconds = 1.5;        ///< s simulated from rest; > 0
};

struct SlidingBlockMotion {
  double distance = 0.0;     ///< m slid in `seconds`
  double whole = 0.0;        ///< m/s^2, 2 distance / seconds^2
  double second_half = 0.0;  ///< m/s^2, the mean acceleration over the second half of `seconds`
};

/// The share of the base's full strength carried after sliding `slid` m (above), in [0, 1].
[[nodiscard]] double mobilised_share(double slid, double length, double shear_modulus);

/// The base's eccentricity, m: how far ahead of the centre the normal push must act to
/// balance the base shear's couple, (height / 2) x shear / normal (Coulomb's block has no
/// moment balance of its own; a box of `height` with its centre of mass mid-height takes
/// it). shear_over_normal >= 0, height >= 0.
[[nodiscard]] double base_eccentricity(double shear_over_normal, double height);

/// The largest eccentricity, m, a rigid base of `length` on Bekker soil of exponent n can
/// carry with its whole length bearing: tilted so that its rear edge just keeps touching,
/// the pressure k z^n grows from 0 at the rear to the front and its centre lies
/// n length / (2 (n + 2)) ahead of the middle. A larger one lifts the rear: the load rides on
/// a front strip of (n + 2)(length / 2 - e), pressed at its front edge deeper than the
/// level base by [(n + 1) length / strip]^(1 / n), and the sliding base's front edge ploughs
/// fresh soil to that depth (docs/terrain.md, "Validation matrix"). n > 0, length > 0.
[[nodiscard]] double bearing_eccentricity_limit(double n, double length);

/// The block's motion from rest: d2s/dt2 = drive - strength mobilised_share(s) while it
/// slides; it stops and holds once it comes to rest with the soil able to hold it.
/// Throws InvalidSetting for a field out of its range.
[[nodiscard]] SlidingBlockMotion slide(const SlidingBlock& b);

}  // namespace shore::scenes
