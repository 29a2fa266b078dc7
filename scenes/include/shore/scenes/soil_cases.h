#pragma once
// Reference cases of bodies on deformable soil, each with its outside reference (Bekker's
// closed forms, the energy balance of the column model): a plate, a wheel pressed or
// towed, a sphere dropped. Written once; used by the shore::bullet tests, the benchmarks
// (speed against error) and the impact scene.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "shore/bullet/terrain_coupling.h"
#include "shore/terrain/height_source.h"
#include "shore/terrain/material.h"
#include "shore/terrain/terrain.h"

namespace shore::scenes {

/// TerrainSettings' defaults with one thread.
[[nodiscard]] inline terrain::TerrainSettings one_thread_terrain() {
  terrain::TerrainSettings s;
  s.threads = 1;
  return s;
}

/// Common knobs of every soil case: the settings structs it varies, embedded whole.
struct SoilRun {
  /// The soil: TerrainSettings' defaults (sand, 1 cm columns, flat at 0), on one thread so
  /// that a case's timings compare across machines (results never depend on threads).
  terrain::TerrainSettings terrain = one_thread_terrain();
  /// How the soil's push is solved and how often the soil steps. Its frame (a Y-up world) is
  /// honoured by run_plate, run_wheel and run_sphere_drop; the other cases refuse a frame
  /// other than the identity.
  bullet::TerrainCouplingSettings coupling;
  double substep = 1.0 / 240;  ///< s, Bullet's fixed substep
  bool body_spray = true;      ///< the case's bodies throw soil (TerrainBodySettings::spray)
  /// Called after every substep (untimed): tests check the volume at every step,
  /// benchmarks follow the spray's peaks. Empty: nothing.
  std::function<void(const terrain::Terrain&, const bullet::TerrainCoupling&)> after_substep;
  /// If set, each substep's wall time (s, as summed into RunStats::wall_seconds) is appended.
  std::vector<double>* substep_seconds = nullptr;
  /// Called on the new soil before the coupling and the bodies are made (a palette and a
  /// painted material map, say). Empty: nothing.
  std::function<void(terrain::Terrain&)> prepare;
};

/// Results common to every case.
struct RunStats {
  std::int64_t substeps = 0;
  double wall_seconds = 0.0;    ///< whole simulation (Bullet + Shore)
  double plugin_seconds = 0.0;  ///< Shore's share (envelopes, soil, push back, reaction)
  double envelope_seconds = 0.0;
  double terrain_seconds = 0.0;
  double push_seconds = 0.0;
  std::uint64_t state_hash = 0;  ///< state_hash (state.h) of the soil and the body at the end
  std::int64_t rescues = 0;      ///< bodies lifted back above bedrock (should stay 0)
  double soil_work = 0.0;        ///< J the body did on the soil (TerrainCouplingStats::plastic_work)
  double shear_work = 0.0;       ///< J of it by shear
  terrain::SprayCounts spray;    ///< the soil's spray at the end
  double spray_seconds = 0.0;    ///< s of wall time the soil spent on spray (part of terrain_seconds)
  /// Adds one substep of a soil coupling's timings (once per coupling and substep).
  void add_coupling_times(const bullet::TerrainCouplingStats& coupling);
  [[nodiscard]] double ms_per_substep() const { return substeps ? 1e3 * wall_seconds / double(substeps) : 0.0; }
  [[nodiscard]] double plugin_ms_per_substep() const {
    return substeps ? 1e3 * plugin_seconds / double(substeps) : 0.0;
  }
};

// ---- a square plate (box) under a uniform pressure --------------------------------------
struct PlateCase {
  SoilRun run;
  double width = 0.3;  ///< m, square footprint side
  /// Where the plate's edges fall, as a fraction of a cell past a column centre: 0.5 puts
  /// them halfway between columns, 0 on column centres.
  double edge_offset = 0.5;
  double pressure = 50e3;     ///< Pa, weight / footprint
  double ramp_seconds = 0.0;  ///< s: weight ramped in linearly over this time; 0 = released at rest
  /// Instead of linearly, the weight ramps in as p s(u)^n, s(u) = 3u^2 - 2u^3, u = t /
  /// ramp_seconds: Bekker's quasi-static sinkage then grows as s(u) and the plate arrives
  /// at rest, as a bevameter's plate does. A linear ramp arrives moving at about
  /// z / (n ramp_seconds), and rigid-plastic soil stops it a further
  /// z / ramp_seconds sqrt(z / (g n^3)) or so deep (+87 % at n 0.13 over 1 s).
  bool ease = false;
  double settle_seconds = 1.0;
};
struct PlateResult {
  double sinkage = 0.0;    ///< m, final depth of the plate's bottom below the original surface
  double reference = 0.0;  ///< m, Bekker: quasi-static if ramped, (n+1)^(1/n) times that if released
  double drift = 0.0;      ///< m the plate moved sideways
  RunStats stats;
};
PlateResult run_plate(const PlateCase& c);

// ---- a rigid wheel, pressed statically or towed -----------------------------------------
struct WheelCase {
  SoilRun run;
  double diameter = 0.8;  ///< m
  double width = 0.3;     ///< m
  double load = 4000.0;   ///< N (the wheel's weight)
  bool towed = false;     ///< false: load ramped in slowly with the wheel held still
  double speed = 1.0;     ///< m/s, towing speed
  double distance = 2.0;  ///< m towed
  double ramp_seconds = 2.0;
};
struct WheelResult {
  double sinkage = 0.0;               ///< m: static, final depth; towed, mean depth over the second half of the run
  double resistance = 0.0;            ///< N, mean towing force over the second half (towed only)
  double rut_depth = 0.0;             ///< m, mean depth of the soil along the track's centre line behind the wheel
  double slip = 0.0;                  ///< mean 1 - v / (omega R) over the second half (towed: negative, a skid)
  double reference_sinkage = 0.0;     ///< m, Bekker: static both-halves integral or rolling formula
  double reference_resistance = 0.0;  ///< N, Bekker compaction resistance (towed)
  RunStats stats;
};
WheelResult run_wheel(const WheelCase& c);

// ---- a driven rigid wheel at a fixed slip (the Wong-Reece rig) ----------------------------
/// The wheel spins at a fixed omega and its carrier moves at a fixed v = (1 - slip) omega r,
/// free to move vertically; the soil's push on it gives drawbar pull and driving torque.
struct DrivenWheelCase {
  SoilRun run;                ///< default material: dry sand (Wong), c 1.04 kPa, phi 28 deg, K 1 cm
  double diameter = 0.6;      ///< m
  double width = 0.15;        ///< m
  double load = 1000.0;       ///< N (the wheel's weight)
  double slip = 0.2;          ///< i = 1 - v / (omega r), in [0, 1)
  double rim_speed = 1.0;     ///< m/s, omega r
  double distance = 1.2;      ///< m travelled by the carrier
  double ramp_seconds = 1.0;  ///< the load ramps in with the wheel held still first
};
struct DrivenWheelResult {
  double sinkage = 0.0;       ///< m, mean depth of the wheel's bottom below the original surface (second half)
  double drawbar_pull = 0.0;  ///< N, mean horizontal push of the soil on the wheel, forward positive (second half)
  double torque = 0.0;        ///< N m, mean driving torque that keeps omega (second half)
  double resistance = 0.0;    ///< N, mean backward push of the soil's normal stresses (compaction, second half)
  RunStats stats;
};
DrivenWheelResult run_driven_wheel(const DrivenWheelCase& c);

// ---- a box resting on a soft slope ------------------------------------------------------
/// A cube on a plane of soil descending along +x at `slope`, released at rest with its
/// bottom on the surface. rigid: the same slope as a rigid Bullet heightfield (the rigid
/// limit, with the material's friction as Bullet's).
struct SlopeBoxCase {
  SoilRun run;
  double slope = 0.26;   ///< rad
  double size = 0.3;     ///< m, side of the square footprint
  double height = 0.0;   ///< m, the box's height; 0: size (a cube)
  double mass = 40.0;    ///< kg
  double seconds = 1.5;  ///< s simulated
  bool rigid = false;
  /// m, the box's start moved across the slope (+y) and down it, in the slope's plane. At 0
  /// its long sides lie on a row of column centres (1 cm columns, a 0.3 m box), where
  /// rounding decides whether an edge row is covered.
  double offset_across = 0.0;
  double offset_down = 0.0;
};
struct SlopeBoxResult {
  double acceleration = 0.0;  ///< m/s^2 along the slope (downhill positive), fitted over the second half
  double end_speed = 0.0;     ///< m/s along the slope at the end
  double max_tilt = 0.0;      ///< rad, the largest angle between the box's up axis and the slope's normal
  double distance = 0.0;      ///< m slid along the slope
  RunStats stats;
};
SlopeBoxResult run_slope_box(const SlopeBoxCase& c);

// ---- a ball rolling down a soft slope ----------------------------------------------------
struct RollingBallCase {
  SoilRun run;
  double slope = 0.26;    ///< rad, the plane descends along +x
  double diameter = 0.3;  ///< m
  double mass = 20.0;     ///< kg
  double seconds = 2.0;   ///< s
  bool rigid = false;     ///< rigid heightfield of the same slope instead of soft soil
};
struct RollingBallResult {
  double distance = 0.0;  ///< m rolled along the slope after `seconds`
  double sinkage = 0.0;   ///< m, mean depth of the ball's bottom below the plane (second half)
  RunStats stats;
};
RollingBallResult run_rolling_ball(const RollingBallCase& c);
/// The distance the ball should roll after t seconds against Bekker's compaction resistance
/// (derived in soil_cases.cpp), and the rolling sinkage z0 that goes with it.
struct RollingBallEstimate {
  double distance = 0.0, sinkage = 0.0, resistance = 0.0;  ///< m, m, N
};
RollingBallEstimate rolling_ball_estimate(const terrain::Material& m, double diameter, double mass, double slope,
                                          double seconds, double gravity = 9.81);

// ---- a wheel pushed sideways, in its rut or on flat ground ------------------------------------
struct SidePushCase {
  SoilRun run;
  double diameter = 0.8, width = 0.3, load = 4000.0;  ///< m, m, N
  bool in_rut = true;           ///< true: towed 1.5 m first, then pushed in its own rut; false: pressed in place
  double push_speed = 0.05;     ///< m/s sideways
  double push_distance = 0.04;  ///< m
};
struct SidePushResult {
  double lateral_force = 0.0;  ///< N, mean sideways push of the soil on the wheel over the second half of the push
  double rut_depth = 0.0;      ///< m, the wheel's depth when the push began
  RunStats stats;
};
SidePushResult run_side_push(const SidePushCase& c);
/// Bekker's bulldozing resistance (N) of a wall of height z (m) and length b (m):
/// b (0.67 c z K_pc + 0.5 z^2 gamma K_pgamma), with Terzaghi's bearing factors; gamma the
/// soil's unit weight (N/m^3).
double bulldozing_resistance(const terrain::Material& m, double z, double b, double unit_weight = 15e3);

// ---- a four-wheel vehicle climbing a sand slope ------------------------------------------
struct VehicleClimbCase {
  SoilRun run;               ///< default cell 2 cm
  double slope = 0.1;        ///< rad, the plane rises along +x
  double seconds = 3.0;      ///< s simulated
  double wheel_speed = 1.0;  ///< m/s, omega r the motors aim for
};
struct VehicleClimbResult {
  double uphill_speed = 0.0;  ///< m/s, the chassis' mean speed up the slope over the last second
  double slip = 0.0;          ///< the wheels' mean slip over the last second, 1 - v / (omega r)
  double wheel_load = 0.0;    ///< N, the weight each wheel carries on the level
  RunStats stats;
};
VehicleClimbResult run_vehicle_climb(const VehicleClimbCase& c);
/// The vehicle's wheel for Wong and Reece's reference (radius, width and load of one wheel).
struct VehicleWheel {
  double radius = 0.3, width = 0.25, load = 0.0;
};
VehicleWheel vehicle_wheel();

// ---- a sphere dropped into the soil -------------------------------------------------------
struct SphereDropCase {
  SoilRun run;
  double diameter = 0.2;  ///< m
  double mass = 10.0;     ///< kg
  double height = 1.0;    ///< m, drop height of the sphere's bottom above the surface
  double seconds = 1.5;   ///< s simulated
  double vx = 0.0;        ///< m/s, horizontal velocity at release (an oblique impact)
  double spin = 0.0;      ///< rad/s about +y at release
};
struct SphereDropResult {
  double depth = 0.0;         ///< m, final depth of the sphere's bottom below the original surface
  double max_depth = 0.0;     ///< m, the deepest it went (less the elastic rebound of unloading soil: depth)
  double reference = 0.0;     ///< m, energy balance of the column model (sphere_drop_reference_depth)
  double energy_lost = 0.0;   ///< J, m g (height + depth)
  double plastic_work = 0.0;  ///< J, sum over soil columns of cell^2 * integral of p_yield dz
  RunStats stats;
};
SphereDropResult run_sphere_drop(const SphereDropCase& c);

/// Depth z at which a sphere dropped from `height` comes to rest in rigid-plastic Bekker
/// soil: m g (height + z) = integral over the crater of (k_c/b + k_phi) z_c^(n+1)/(n+1) dA,
/// with z_c the local depth of the spherical cap and b the crater's diameter. Solved by
/// quadrature and bisection, independently of the column model.
double sphere_drop_reference_depth(const terrain::Material& m, double diameter, double mass, double height,
                                   double gravity = 9.81);

/// The same balance with the soil's shear on the sphere's surface as well: each column's
/// Janosi-Hanamoto stress (c + sigma tan phi)(1 - exp(-j / K)), sigma its Bekker pressure,
/// j the slide of the surface over it against soil at rest (the cap depth times sin beta,
/// beta the surface's tilt), resisting the fall by tau tan(beta) per unit plan area: the
/// shear the wheels' references (Wong and Reece) carry on their rims, which Bekker's plate
/// law, and so the plain balance, leaves out. On soil without strength it is the plain
/// balance. The validation matrix judges its sphere against it (docs/terrain.md,
/// "Validation matrix").
double sphere_drop_reference_depth_with_shear(const terrain::Material& m, double diameter, double mass, double height,
                                              double gravity = 9.81);

}  // namespace shore::scenes
