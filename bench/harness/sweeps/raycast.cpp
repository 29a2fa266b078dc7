// raycast: Bullet's raycast vehicles on Shore's soil. What a raycast wheel costs per
// substep, everything of Shore's included (its press, its share of the soil step, its
// tiles), against the same car on a plain Bullet plane in the same run; a SoilVehicle's
// driven wheels against Wong and Reece; a towed wheel's rolling sinkage against Bekker.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "shore/scenes/raycast_cases.h"
#include "shore/scenes/wong_reece.h"
#include "shore/terrain/bekker.h"
#include "sweep.h"
#include "sweep_util.h"

namespace shore::bench {
namespace {

/// Runs on soil and on a plane alternated; the median over pairs of the per-wheel difference.
void wheel_cost(const SweepContext& ctx, SweepResult& out) {
  Table& t = out.table("raycast_wheel_cost",
                       {"pair", "soil_ms_per_substep", "plane_ms_per_substep", "wheel_us_per_substep", "distance_m"});
  std::vector<double> per_wheel;
  const int pairs = ctx.quick ? 3 : 7;
  for (int k = 0; k < pairs; ++k) {
    ctx.progress("raycast car on 1 cm sand and on a plane, pair " + std::to_string(k + 1));
    scenes::RaycastCostCase c;
    const scenes::RaycastCostResult soil = scenes::run_raycast_cost(c);
    c.on_plane = true;
    const scenes::RaycastCostResult plane = scenes::run_raycast_cost(c);
    const double soil_ms = 1e3 * soil.wall_seconds / double(soil.substeps);
    const double plane_ms = 1e3 * plane.wall_seconds / double(plane.substeps);
    per_wheel.push_back(1e3 * (soil_ms - plane_ms) / 4.0);
    t.add({double(k), soil_ms, plane_ms, per_wheel.back(), soil.distance});
  }
  std::sort(per_wheel.begin(), per_wheel.end());
  const double us = per_wheel[per_wheel.size() / 2];
  out.figure("plugin.raycast_wheel_us_per_substep", us, "us per wheel per substep, Shore's share (median of pairs)");
  out.target({.key = "plugin.raycast_wheel_us_per_substep",
              .what = "a raycast wheel on 1 cm sand, everything of Shore's included",
              .value = us,
              .op = "<=",
              .threshold = 50.0,
              .unit = "us per substep"});
}

void driven_wheels(const SweepContext& ctx, SweepResult& out) {
  Table& t =
      out.table("raycast_driven", {"slip", "slip_measured", "load_N", "pull_N", "wong_reece_pull_N", "pull_error_W",
                                   "torque_Nm", "wong_reece_torque_Nm", "sinkage_m", "wong_reece_sinkage_m"});
  double worst = 0.0;
  for (const double slip : {0.1, 0.2, 0.3, 0.5}) {
    ctx.progress("SoilVehicle driven at slip " + std::to_string(slip));
    scenes::RaycastTowCase c;
    const scenes::WongReeceWheel wheel;
    c.car.mass = 4 * wheel.load / 9.81;
    c.car.wheel_radius = wheel.radius;
    c.car.wheel_width = wheel.width;
    c.car.soil_traction = true;
    c.speed = 0.5;
    c.seconds = 4.0;
    c.average_from = 0.5;
    c.slip = slip;
    const scenes::RaycastTowResult r = scenes::run_raycast_tow(c);
    scenes::WongReeceWheel ref;
    ref.load = r.load;
    const scenes::WongReeceResult want = scenes::wong_reece(ref, slip);
    const double error = (r.pull - want.drawbar_pull) / r.load;
    worst = std::max(worst, std::abs(error));
    t.add({slip, r.slip, r.load, r.pull, want.drawbar_pull, error, r.torque, want.torque, r.sinkage, want.sinkage});
  }
  out.figure("plugin.raycast_wheel_drawbar_pull_error_max", worst, "W, the largest |pull - Wong-Reece| / load");
  out.target({.key = "plugin.raycast_wheel_drawbar_pull_error_max",
              .what = "a SoilVehicle's driven wheels (D 0.6 m, b 0.15 m, dry sand) at slips 0.1-0.5 vs Wong-Reece",
              .value = worst,
              .op = "<=",
              .threshold = 0.08,
              .unit = "W"});
}

void towed_wheels(const SweepContext& ctx, SweepResult& out) {
  Table& t = out.table("raycast_towed", {"material", "load_N", "rut_m", "bekker_rolling_m", "error_pct", "resistance_N",
                                         "bekker_compaction_N", "resistance_error_pct"});
  double worst = 0.0;
  for (const char* name : {"sand", "mud"}) {
    ctx.progress(std::string("towed raycast car on ") + name);
    scenes::RaycastTowCase c;
    c.material = terrain::Material::preset(name);
    c.car.mass = 4 * 4000.0 / 9.81;  // D 0.8 m, b 0.3 m, 4 kN a wheel
    const scenes::RaycastTowResult r = scenes::run_raycast_tow(c);
    const double rolling = terrain::bekker::wheel_sinkage_rolling(c.material, r.load, 0.8, 0.3);
    const double compaction = terrain::bekker::wheel_compaction_resistance(c.material, rolling, 0.3);
    const double error = error_pct(r.rut, rolling);
    worst = std::max(worst, std::abs(error));
    t.add({name, r.load, r.rut, rolling, error, -r.resistance, compaction, error_pct(-r.resistance, compaction)});
  }
  out.figure("plugin.raycast_wheel_rolling_sinkage_error_pct", worst, "% (largest of sand and mud) vs Bekker's z0");
  out.target({.key = "plugin.raycast_wheel_rolling_sinkage_error_pct",
              .what = "a towed raycast wheel's rut (D 0.8 m, b 0.3 m, 4 kN) vs Bekker's rolling sinkage",
              .value = worst,
              .op = "<=",
              .threshold = 10.0,
              .unit = "%"});
}

void run(const SweepContext& ctx, SweepResult& out) {
  wheel_cost(ctx, out);
  driven_wheels(ctx, out);
  towed_wheels(ctx, out);
  out.note(
      "Raycast wheels: cost = (whole world step of a four-wheel-drive SoilVehicle, 800 kg, D 0.8 m, b 0.3 m, "
      "accelerating on 1 cm sand at 1/240 s, minus the same car on a Bullet static plane) / 4 wheels, runs "
      "alternated, the median over pairs. Driven: the car on four of Wong and Reece's wheels (D 0.6 m, b 0.15 m, "
      "1 kN each) towed at 0.5 m/s with every wheel held at the slip's spin, the front wheels' means over the "
      "second half against wong_reece at their load. Towed: the heavy car (4 kN a wheel) towed at 1 m/s, the "
      "front wheel's rut between the axles against Bekker's rolling sinkage and the front wheels' push against "
      "Bekker's compaction resistance.");
}

const SweepRegistrar kRegistered{Sweep{
    .name = "raycast",
    .description = "raycast vehicles on soil: a wheel's cost, driven wheels vs Wong-Reece, towed vs Bekker",
    .run = run,
}};

}  // namespace
}  // namespace shore::bench
