// contact: bodies feeling the shape of the soil. A driven rigid wheel's drawbar pull,
// torque and sinkage against slip (Wong and Reece, and the plain column model's front-only
// version of the same formulas); boxes on soft slopes against Coulomb; a four-wheel
// vehicle's steepest climb against tan(alpha) = DP / W; what resting bodies cost.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "shore/bullet/terrain_coupling.h"
#include "shore/scenes/soil_cases.h"
#include "shore/scenes/wong_reece.h"
#include "shore/scenes/world.h"
#include "sweep.h"
#include "sweep_util.h"

namespace shore::bench {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kGravity = 9.81;

void drawbar_sweep(const SweepContext& ctx, SweepResult& out) {
  Table& t =
      out.table("contact_drawbar", {"curve", "slip", "pull_over_load", "torque_nm", "sinkage_m", "pull_error_over_load",
                                    "torque_error_pct", "sinkage_error_pct", "ms_per_substep"});
  const std::vector<double> slips =
      ctx.quick ? std::vector<double>{0.1, 0.2, 0.3, 0.5} : std::vector<double>{0.05, 0.1, 0.2, 0.3, 0.5, 0.7};
  scenes::WongReeceWheel ref, front_only;
  front_only.front_only = true;
  double worst_pull = 0.0, worst_torque = 0.0, worst_sinkage = 0.0;
  for (const double slip : slips) {
    ctx.progress("driven wheel at slip " + std::to_string(slip));
    scenes::DrivenWheelCase c;
    c.slip = slip;
    c.run.terrain.threads = 1;
    const scenes::DrivenWheelResult r = scenes::run_driven_wheel(c);
    const scenes::WongReeceResult want = scenes::wong_reece(ref, slip), plain = scenes::wong_reece(front_only, slip);
    const double pull_error = std::abs(r.drawbar_pull - want.drawbar_pull) / c.load;
    const double torque_error = error_pct(r.torque, want.torque), sinkage_error = error_pct(r.sinkage, want.sinkage);
    worst_pull = std::max(worst_pull, pull_error);
    worst_torque = std::max(worst_torque, std::abs(torque_error));
    worst_sinkage = std::max(worst_sinkage, std::abs(sinkage_error));
    t.add({"Shore", slip, r.drawbar_pull / c.load, r.torque, r.sinkage, pull_error, torque_error, sinkage_error,
           r.stats.ms_per_substep()});
    t.add({"Wong-Reece", slip, want.drawbar_pull / c.load, want.torque, want.sinkage, 0.0, 0.0, 0.0, 0.0});
    t.add({"front-only column model", slip, plain.drawbar_pull / c.load, plain.torque, plain.sinkage,
           std::abs(plain.drawbar_pull - want.drawbar_pull) / c.load, error_pct(plain.torque, want.torque),
           error_pct(plain.sinkage, want.sinkage), 0.0});
  }
  out.figure("plugin.drawbar_pull_error_max", worst_pull, "of the load (largest |DP - DP_ref| / W over the slips)");
  out.figure("plugin.drive_torque_error_max_pct", worst_torque, "% (largest over the slips)");
  out.figure("plugin.drive_sinkage_error_max_pct", worst_sinkage, "% (largest over the slips)");
  out.target({.key = "plugin.drawbar_pull_error_max",
              .what = "driven wheel's drawbar pull against Wong-Reece, slips 0.1 to 0.5",
              .value = worst_pull,
              .op = "<=",
              .threshold = 0.08,
              .unit = "of W"});
  out.plot({.name = "contact_drawbar_vs_slip",
            .title = "Driven wheel D 0.6 m, b 0.15 m, 1 kN, dry sand: drawbar pull against slip",
            .table = "contact_drawbar",
            .x = "slip",
            .y = "pull_over_load",
            .series = "curve",
            .x_label = "slip",
            .y_label = "drawbar pull / load",
            .log_x = false,
            .log_y = false});
  out.note(
      "Driven wheel (the Wong-Reece rig of the contact issue): D 0.6 m, b 0.15 m, 1000 N on 1 cm dry sand "
      "(n 1.1, k_c 0.99, k_phi 1528.43 kN, c 1.04 kPa, phi 28 deg, K 1 cm), spinning at omega r = 1 m/s while its "
      "carrier moves at (1 - i) omega r, free vertically, 1/240 s, one thread; means over the second half of 1.2 m. "
      "References: Wong and Reece's integrals (scenes/src/wong_reece.cpp, the formulas of refs/wong_reece.py) and "
      "the same with Bekker's stress on the front arc only, what a plain column model gives.");
}

/// Coulomb's acceleration down a slope (c = 0), or g sin(theta) without friction.
double coulomb(double slope, double friction_angle) {
  return kGravity * (std::sin(slope) - std::tan(friction_angle) * std::cos(slope));
}

void slope_sweep(const SweepContext& ctx, SweepResult& out) {
  Table& t = out.table("contact_slope", {"material", "slope_deg", "acceleration_m_s2", "reference_m_s2", "error_pct",
                                         "max_tilt_deg", "rigid_heightfield_m_s2", "rigid_plastic_m_s2",
                                         "rigid_plastic_error_pct", "rigid_plastic_max_tilt_deg"});
  struct Case {
    std::string name;
    double slope_deg;
    double friction_angle;
  };
  const std::vector<Case> cases = {{"frictionless", 15, 0.0},
                                   {"frictionless", 25, 0.0},
                                   {"Coulomb phi 28", 35, 28 * kDeg},
                                   {"Coulomb phi 28", 40, 28 * kDeg}};
  double worst = 0.0, worst_rigid_plastic = 0.0;
  for (const Case& k : cases) {
    ctx.progress("box on a " + std::to_string(int(k.slope_deg)) + " degree slope, " + k.name);
    scenes::SlopeBoxCase c;
    c.slope = k.slope_deg * kDeg;
    c.run.terrain.material = terrain::Material::sand();
    c.run.terrain.material.alpha = 0.0;
    c.run.terrain.material.cohesion = 0.0;
    c.run.terrain.material.friction_angle = k.friction_angle;
    c.run.terrain.material.remould_ratio = c.run.terrain.material.remould_shear_ratio = 0.0;
    c.run.terrain.threads = 1;
    const scenes::SlopeBoxResult r = scenes::run_slope_box(c);  // the preset's elastic unloading
    c.run.terrain.material.unload_modulus = 0.0;
    const scenes::SlopeBoxResult plastic = scenes::run_slope_box(c);
    c.rigid = true;
    const scenes::SlopeBoxResult rigid = scenes::run_slope_box(c);
    const double want = coulomb(c.slope, k.friction_angle), error = error_pct(r.acceleration, want);
    const double error_plastic = error_pct(plastic.acceleration, want);
    worst = std::max(worst, std::abs(error) / 100.0);
    worst_rigid_plastic = std::max(worst_rigid_plastic, std::abs(error_plastic) / 100.0);
    t.add({k.name, k.slope_deg, r.acceleration, want, error, r.max_tilt / kDeg, rigid.acceleration,
           plastic.acceleration, error_plastic, plastic.max_tilt / kDeg});
  }
  out.figure("plugin.slope_slide_error_max_rigid_plastic", worst_rigid_plastic,
             "relative, the same boxes on rigid-plastic columns (Material::unload_modulus 0)");
  out.figure("plugin.slope_slide_error_max", worst, "relative (box sliding on soft slopes vs Coulomb)");
  out.target({.key = "plugin.slope_slide_error_max",
              .what = "box sliding down soft slopes against Coulomb (15-40 deg)",
              .value = worst,
              .op = "<=",
              .threshold = 0.10,
              .unit = "relative"});
  out.note(
      "Slopes: a 0.3 m, 40 kg box released on a plane of 1 cm sand (c 0, no softening) at 1/240 s; acceleration "
      "fitted over the second half of 1.5 s against Coulomb (g sin theta frictionless, g (sin theta - tan phi "
      "cos theta) with phi 28 deg). A box whose tilt grows past 45 degrees tumbled (why: docs/terrain.md, "
      "'Unloading'). The sand preset unloads elastically (unload_modulus 5.03e8 Pa/m^2), which makes the "
      "pressure under the box follow its pose; the rigid_plastic columns repeat each case without it "
      "(unload_modulus 0), where the box digs in along its pitched underside and tumbles. The rigid column is Bullet "
      "on Shore's rigid tiles of the same slope "
      "(internal-edge info "
      "on) with friction tan phi: exact without friction, 10-20 % below Coulomb with it.");
}

void climb_sweep(const SweepContext& ctx, SweepResult& out) {
  Table& t = out.table("contact_climb", {"slope_deg", "uphill_speed_m_s", "slip", "climbs"});
  double lo = 0.0, hi = 20.0 * kDeg, slip_at_lo = 0.0;  // climbs at lo, stalls at hi
  for (int it = 0; it < (ctx.quick ? 4 : 6); ++it) {
    const double mid = 0.5 * (lo + hi);
    ctx.progress("vehicle on a " + std::to_string(mid / kDeg) + " degree sand slope");
    scenes::VehicleClimbCase c;
    c.slope = mid;
    c.run.terrain.threads = 1;
    const scenes::VehicleClimbResult r = scenes::run_vehicle_climb(c);
    const bool climbs = r.uphill_speed > 0.2;
    t.add({mid / kDeg, r.uphill_speed, r.slip, climbs ? 1.0 : 0.0});
    if (climbs) {
      lo = mid;
      slip_at_lo = r.slip;
    } else {
      hi = mid;
    }
  }
  scenes::WongReeceWheel w;
  const scenes::VehicleWheel vw = scenes::vehicle_wheel();
  w.radius = vw.radius, w.width = vw.width, w.load = vw.load;
  double best = 0.0;
  for (double slip = 0.02; slip < 0.9; slip += 0.02) best = std::max(best, scenes::wong_reece(w, slip).drawbar_pull);
  const double at_slip = scenes::wong_reece(w, std::clamp(slip_at_lo, 0.0, 0.95)).drawbar_pull;
  const double steepest = 0.5 * (lo + hi);
  out.figure("plugin.vehicle_climb_deg", steepest / kDeg, "deg, the steepest 2 cm sand slope the vehicle climbs");
  out.figure("plugin.vehicle_climb_reference_deg", std::atan(best / vw.load) / kDeg,
             "deg, atan(DP / W) at the wheels' best slip (Wong-Reece)");
  out.figure("plugin.vehicle_climb_reference_at_slip_deg", std::atan(at_slip / vw.load) / kDeg,
             "deg, atan(DP / W) at the slip measured on the steepest slope climbed");
  out.figure("plugin.vehicle_climb_slip", slip_at_lo, "slip on the steepest slope climbed");
  out.note(
      "Vehicle climb: the four-wheel vehicle (400 kg chassis, four 25 kg wheels D 0.6 m, b 0.25 m, motors aiming "
      "at 1 m/s) released facing up a plane of 2 cm dry sand for 3 s; it climbs if it moves up at more than 0.2 "
      "m/s over the last second. The steepest slope is bisected; the reference is Wong and Reece's pull for one "
      "wheel at its load.");
}

void resting_bodies(const SweepContext& ctx, SweepResult& out) {
  ctx.progress("100 boxes at rest on 1 cm sand");
  terrain::TerrainSettings s;
  s.threads = 1;
  terrain::Terrain soil(s);
  scenes::World world;
  bullet::TerrainCoupling ground(world.world(), soil);
  std::vector<btRigidBody*> boxes;
  for (int k = 0; k < 100; ++k) {
    btRigidBody* box = world.add_body(std::make_unique<btBoxShape>(btVector3(0.1f, 0.1f, 0.1f)), 20.0,
                                      btVector3(btScalar(0.4 * (k % 10)), btScalar(0.4 * (k / 10)), 0.101f));
    box->setActivationState(DISABLE_DEACTIVATION);  // held still by the soil, not asleep
    ground.add_body(box);
    boxes.push_back(box);
  }
  const double h = 1.0 / 240;
  for (int k = 0; k < 480; ++k) world.step(h);  // settle
  double plugin = 0.0, whole = 0.0;
  const int n = ctx.quick ? 240 : 960;
  for (int k = 0; k < n; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    world.step(h);
    whole += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const bullet::TerrainCouplingStats& g = ground.stats();
    plugin += g.envelope_seconds + g.terrain_seconds + g.push_seconds + g.reaction_seconds;
  }
  double speed = 0.0;
  for (const btRigidBody* b : boxes) speed = std::max(speed, double(b->getLinearVelocity().length()));
  Table& t = out.table("contact_resting", {"bodies", "plugin_ms_per_substep", "whole_ms_per_substep",
                                           "us_per_body_per_substep", "max_speed_m_s"});
  const double us_per_body = 1e6 * plugin / n / double(boxes.size());
  t.add({double(boxes.size()), 1e3 * plugin / n, 1e3 * whole / n, us_per_body, speed});
  out.figure("plugin.resting_body_us_per_substep", us_per_body, "us per body per substep (Shore's own time)");
  out.figure("plugin.resting_100_boxes_ms_per_substep", 1e3 * plugin / n, "ms per substep for all 100 (Shore)");
  out.target({.key = "plugin.resting_body_us_per_substep",
              .what = "a box held at rest by the soil (awake)",
              .value = us_per_body,
              .op = "<=",
              .threshold = 10.0,
              .unit = "us/substep"});
  out.note(
      "Resting bodies: 100 boxes of 0.2 m and 20 kg on 1 cm sand, kept awake (Bullet would put them to sleep, "
      "which costs nothing), settled for 2 s, then timed: Shore's own time per substep and body. A body at rest "
      "keeps last substep's contact blocks and reruns the warm-started solve only.");
}

void run(const SweepContext& ctx, SweepResult& out) {
  drawbar_sweep(ctx, out);
  slope_sweep(ctx, out);
  resting_bodies(ctx, out);
  climb_sweep(ctx, out);
}

const SweepRegistrar kRegistered{Sweep{
    .name = "contact",
    .description = "soil contact: driven wheel vs Wong-Reece, boxes on slopes vs Coulomb, vehicle climb, resting cost",
    .run = run,
}};

}  // namespace
}  // namespace shore::bench
