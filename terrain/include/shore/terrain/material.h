#pragma once
// Soil materials: the appearance parameters of Sumner, O'Brien & Hodgins (1998, Table 1),
// Bekker's pressure-sinkage and Janosi-Hanamoto's shear parameters (Wong, Theory of Ground
// Vehicles, ch. 2), the loss of bearing in sheared soil, and soil depth. Angles in
// radians, lengths in metres, pressures in Pa.

#include <numbers>
#include <string>

#include "shore/terrain/spray.h"

namespace shore::terrain {

struct Material {
  std::string name = "sand";

  // ---- appearance (Sumner et al. Table 1) ----
  double theta_stop = 0.8;   ///< rad, (0, pi/2]: erosion stops when every slope is below this ("liquidity")
  double sigma = 0.2;        ///< [0, 1]: share of the excess height difference moved per pass ("roughness")
  double theta_in = 0.8;     ///< rad, (0, pi/2]: steepest stable slope toward a column the body touches
  double theta_out = 0.436;  ///< rad, (0, pi/2]: angle of repose elsewhere
  double alpha = 0.3;        ///< [0, 1]: share of displaced soil pushed to the rim; the rest is compressed

  // ---- bearing (Bekker: p = (k_c / b + k_phi) z^n) ----
  double bekker_n = 1.1;           ///< sinkage exponent, (0, 3)
  double bekker_kc = 0.99e3;       ///< cohesive modulus, N/m^(n+1), >= 0
  double bekker_kphi = 1528.43e3;  ///< frictional modulus, N/m^(n+2), >= 0 (k_c + k_phi > 0)

  // ---- shear (Janosi-Hanamoto: tau = (c + sigma tan phi)(1 - exp(-j / K))) ----
  double cohesion = 1.04e3;                                 ///< c, Pa, >= 0
  double friction_angle = 28.0 * std::numbers::pi / 180.0;  ///< phi, rad, [0, pi/2)
  double shear_modulus = 0.01;  ///< K, m, > 0: shear displacement at which 63 % of the strength acts
  /// Sheared soil is remoulded: it is loosened, bearing at sinkage z what intact soil bears
  /// at s z, s = 1 - remould_ratio (1 - exp(-j / remould_length)) (Bekker's pressure times
  /// s^n), and its shear strength is multiplied by 1 - remould_shear_ratio (1 - exp(-j /
  /// remould_length)), j the shear displacement (for the strength, under a Bullet body, the
  /// shear the column had taken when it last yielded: soil that carries a sliding body
  /// elastically keeps its strength). This is what makes a slipping wheel dig in
  /// (slip sinkage, a multiple 1 / s of the sinkage whatever n) and its pull level off with
  /// slip. Calibrated for dry sand against Wong and Reece's driven wheel; because the loss
  /// acts on the sinkage, not the pressure, the same ratios hold Wong-Reece's pull and
  /// sinkage on the other soils of Wong's table (docs/terrain.md, "Validation matrix");
  /// each in [0, 1). 0 and 0: rigid-plastic soil that never softens. 0.516: sand keeps
  /// 0.484^1.1 = 0.45 of its bearing fully sheared, as it did with the earlier
  /// pressure-share law (0.55).
  double remould_ratio = 0.516;
  double remould_shear_ratio = 0.22;
  double remould_length = 0.06;  ///< m, > 0
  /// Unloading-reloading (Wong's k_u = A_u z, k_0 = 0): a column pressed to plastic sinkage
  /// z and then relieved springs back elastically with stiffness k_u = unload_modulus x z
  /// (Pa/m; at least p_yield / z, so it never springs back above the ground it was pressed
  /// from), so a body lifted by g off it still feels (p_yield(z) - k_u g) until it is
  /// p_yield / k_u clear, and the pressure under a body follows its pose: a box slides down
  /// a soft slope at Coulomb's rate instead of tumbling (docs/terrain.md, "Unloading"). A
  /// column pushes at most with what it carried at the end of the last substep (the soil
  /// coupling keeps that per column), so soil that erosion lays under a body carries nothing
  /// until the body presses it. Pa/m^2, >= 0; 0: rigid-plastic columns (they hold anything up
  /// to their yield pressure without deflecting). Default (sand) 5.03e8, the order of Wong's
  /// A_u for sand (Theory of Ground Vehicles, response to repetitive loading): its reach
  /// p_yield / k_u is about 2 mm at 0.1 m of sinkage. Mud and snow presets: 0. At the
  /// clayey soils' A_u (about 1.4e8) the reach is the whole sinkage at the few millimetres a
  /// game's loads press mud (released plates rest 6.5 % high, measured) and snow compacts
  /// without springing back; neither is calibrated yet.
  double unload_modulus = 5.03e8;

  /// Bullet friction coefficient of rigid ground, and of soft ground for bodies Shore does
  /// not couple (they collide with the heightfield tiles through Bullet). Coupled bodies
  /// feel the shear law above instead. >= 0.
  double friction = 0.6;
  double soil_depth = 1.0;  ///< m, > 0: deformable soil above bedrock
  bool rigid = false;       ///< true: the ground never deforms (rock, asphalt)
  /// How fast bodies throw it into the air (shore/terrain/spray.h); docs/terrain.md,
  /// "Spray", says why the presets chose their values.
  SprayMaterial spray;

  /// Throws shore::InvalidSetting naming the field, the value and the allowed range.
  void validate() const;

  /// Dry sand (Wong): n 1.1, k_c 0.99 kN/m^2.1, k_phi 1528.43 kN/m^3.1; c 1.04 kPa,
  /// phi 28 degrees, K 1 cm.
  /// Spray (Sumner et al. gave sand particles): adhesion 1 mm (a film two grains thick:
  /// dry grains barely cling), half life 0.04 s (they fall off at once: a wheel turning at
  /// 10 rad/s has shed half within a quarter turn, so the rooster tail starts right behind
  /// the contact), s 2.5 m/s and gamma 2 (a running foot's toe-off or a tyre spinning at a
  /// few m/s throws nearly all of it, a walking foot at 1 m/s about a sixth), particles of
  /// 4 mm (grain clusters a 1 to 2 cm grid can show, three per 1 cm column), min speed
  /// 0.3 m/s, jitter 0.2, drag 0.6 /s (a 4 mm grain's terminal speed is about 15 m/s).
  static Material sand();
  /// Clayey soil, 55 % moisture (Wong): n 0.7, k_c 16.03, k_phi 1262.53; c 2.07 kPa,
  /// phi 10 degrees; K 1 cm (a typical value; Wong gives none for this soil).
  /// Spray: adhesion 4 mm (wet clay cakes onto tyres and boots), half life 0.3 s (it
  /// clings for about a wheel turn), s 6 m/s and gamma 2 (only fast wheels fling mud; a
  /// foot lifts it and drops it as clumps), clods of 12 mm, min speed 0.5 m/s, jitter 0.3,
  /// drag 0.3 /s (heavy clods keep their speed).
  static Material mud();
  /// Snow, U.S. (Wong): n 1.6, k_c 4.37, k_phi 196.72; c 1.03 kPa, phi 19.7 degrees;
  /// K 2.5 cm (a typical value for fresh snow).
  /// Spray: adhesion 2 mm, half life 0.1 s, s 4 m/s and gamma 2 (running in snow throws
  /// clumps rather than grains, Sumner et al. observe; skis and tyres throw more), clumps
  /// of 8 mm, min speed 0.3 m/s, jitter 0.3, drag 2.5 /s (fluffy clumps fall at about
  /// 4 m/s at most).
  static Material snow();
  /// Ground that does not deform (nor sprays: adhesion 0).
  static Material rigid_ground();
  /// Looks a preset up by name ("sand", "mud", "snow", "rigid"); throws InvalidSetting otherwise.
  static Material preset(const std::string& name);
};

}  // namespace shore::terrain
