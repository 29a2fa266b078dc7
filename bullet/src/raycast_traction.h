#pragma once
// Internal: the soil's shear on a raycast wheel's rim. Each strip of the rim across the
// wheel (one cell long, at angle theta from the bottom) takes Janosi-Hanamoto's shear,
// tau = (c + sigma tan phi)(1 - exp(-j / K)), with Wong and Reece's shear displacement
// along the rim,
//   j_x(theta) = r [(theta_1 - theta) - (1 - i)(sin theta_1 - sin theta)],
// theta_1 the entry angle, i the slip, and sideways the distance the wheel has slid across
// the soil while the strip's soil passed under it, j_y = v_y t(theta). The shear acts
// against the slip displacement (j_x, j_y): its size follows |j| (longitudinal and lateral
// slip share one strength), its direction j's. Sheared soil loses part of its strength,
// 1 - a (1 - exp(-|j| / L)) (Material::remould_shear_ratio, remould_length), as under the
// rigid-body contact.
//
// The wheel's spin is not integrated: it is found each substep so that the rim's shear
// balances what drives or brakes the wheel (its engine force at the rim, less the brake),
// the wheel's own inertia neglected (a raycast wheel has none in Bullet). A wheel asked for
// more than the soil can take spins at the largest spin considered; a braked wheel the soil
// cannot turn stays locked. The search starts from the spin the wheel had in the last
// substep when it had one (a wheel's spin changes little from one substep to the next):
// the same root, narrowed to the same width, in about a third of the rim's evaluations.

#include <limits>
#include <span>

#include "shore/bullet/config.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

/// One strip of the rim in contact.
struct RimStrip {
  double theta = 0.0;  ///< rad, from the bottom, positive ahead along the heading
  double sin_theta = 0.0;
  double cos_theta = 1.0;
  double strength = 0.0;  ///< N, (c + sigma tan phi) times the strip's rim area: its full shear
};

struct TractionInput {
  double radius = 0.0;               ///< m
  double entry_angle = 0.0;          ///< rad, theta_1 >= every strip's theta: where soil meets the rim
  double exit_angle = 0.0;           ///< rad, theta at the rear edge (<= every strip's theta)
  double shear_modulus = 0.01;       ///< K, m
  double remould_shear_ratio = 0.0;  ///< a: the share of strength fully sheared soil loses
  double remould_length = 0.06;      ///< L, m
  double forward_speed = 0.0;        ///< m/s, the contact point's velocity along the heading
  double side_speed = 0.0;           ///< m/s, along the axle
  double drive = 0.0;                ///< N at the rim along the heading (Bullet's engine force)
  double brake = 0.0;                ///< N at the rim, >= 0: the most the brake resists the spin with
  double held_spin = 0.0;            ///< rad/s, used when `hold` (a speed-controlled wheel)
  bool hold = false;
  /// rad/s, positive rolling forward: the wheel's spin in the last substep, where the search
  /// for the balancing spin starts; NaN: none (the search brackets the whole range).
  double last_spin = std::numeric_limits<double>::quiet_NaN();
};

/// Wong and Reece's shear displacement along the rim at the spin found, to read |j| at any
/// angle of the rim: the soil there has been sheared by it (what loosens it, shear::loosening).
struct RimShear {
  double dir = 1.0;        ///< +1 rolling along the heading, -1 against it
  double radius = 0.0;     ///< m
  double entry = 0.0;      ///< rad, theta_1 in the rolling frame
  double sin_entry = 0.0;  ///< sin(entry)
  double rim = 0.0;        ///< the rim's speed over the slip's scale (1 for a driven wheel)
  double ground = 0.0;     ///< the ground's speed over the slip's scale (1 - i for a driven wheel)
  double side = 0.0;       ///< the sideways speed over the slip's scale
  /// m, |j| at rim angle theta (rad from the bottom, positive ahead along the heading, as
  /// RimStrip::theta): the rim_force's j; 0 for a default RimShear.
  [[nodiscard]] double at(double theta) const;
};

struct Traction {
  double spin = 0.0;     ///< rad/s, positive rolling forward
  double slip = 0.0;     ///< Wong's i = 1 - v / (omega r) driving (1 against the motion), omega r / v - 1 braking
  double forward = 0.0;  ///< N on the chassis along the heading (thrust: the rim's shear, horizontal)
  double side = 0.0;     ///< N on the chassis along the axle
  double torque = 0.0;   ///< N m, the shear's moment about the axle (what drives the wheel)
  RimShear shear;        ///< j along the rim at this spin
};

/// Below this (m/s) a slip velocity is measured against it rather than the wheel's speed:
/// a wheel starting from rest mobilises its shear over the first few mm, not at once.
inline constexpr double kTractionSpeedFloor = 0.005;

/// The rim's shear for the wheel's spin (held, or balancing drive and brake).
Traction soil_traction(std::span<const RimStrip> rim, const TractionInput& in);

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
