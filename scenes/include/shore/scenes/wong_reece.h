#pragma once
// Wong and Reece's driven rigid wheel (J. Terramechanics 4(1), 1967; Wong, Theory of Ground
// Vehicles, ch. 5): the outside reference for drawbar pull, torque and sinkage against slip.
//
// Normal stress from Bekker, sigma = (k_c / b + k_phi) z^n, on the front arc theta_m..theta_1
// and mapped onto the rear arc 0..theta_m, theta_m = (c1 + c2 i) theta_1; shear from
// Janosi-Hanamoto, tau = (c + sigma tan phi)(1 - exp(-j / K)), with the shear displacement
// j(theta) = r [(theta_1 - theta) - (1 - i)(sin theta_1 - sin theta)]. theta_1 is found so the
// vertical force equals the load; drawbar pull = thrust - compaction resistance.

#include "shore/terrain/material.h"

namespace shore::scenes {

struct WongReeceWheel {
  double radius = 0.3;                                 ///< m
  double width = 0.15;                                 ///< m
  double load = 1000.0;                                ///< N
  terrain::Material soil = terrain::Material::sand();  ///< n, k_c, k_phi, cohesion, friction_angle, shear_modulus
  double c1 = 0.43, c2 = 0.32;  ///< where the normal stress peaks (Wong and Reece's values for sand)
  /// Bekker's stress on the front arc only, none behind the bottom: what a plain column
  /// model of rigid-plastic soil gives.
  bool front_only = false;
};

struct WongReeceResult {
  double sinkage = 0.0;       ///< m
  double drawbar_pull = 0.0;  ///< N
  double torque = 0.0;        ///< N m
  double thrust = 0.0;        ///< N
  double resistance = 0.0;    ///< N (compaction)
  double entry_angle = 0.0;   ///< rad, theta_1
};

/// The wheel at slip i in (-1, 1): driven at i > 0, skidding (braked) at i < 0.
WongReeceResult wong_reece(const WongReeceWheel& wheel, double slip);

/// A towed wheel: free on its axle, so the soil's torque on it vanishes. Its slip is a
/// small skid (i < 0), where the rim's shear ahead of the bottom, backward, balances the
/// shear behind it; the shear still carries part of the load (tau sin(theta)), so on soil
/// with strength it sinks less than Bekker's pressure alone would sink it.
struct TowedWongReeceResult {
  double slip = 0.0;      ///< the skid at which the torque vanishes (<= 0)
  WongReeceResult wheel;  ///< the wheel there (its torque ~0)
};
[[nodiscard]] TowedWongReeceResult wong_reece_towed(const WongReeceWheel& wheel);

}  // namespace shore::scenes
