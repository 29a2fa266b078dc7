// coupling: what the Bullet plugin costs per substep, and how right it is. Water: bodies
// floating in a pool (shore::scenes::run_pool) against Archimedes' draft, across water
// resolution and substep. Soil: the plugin's own time for one towed wheel (envelope, soil
// step, tile update separately), what the settings that trade its accuracy for speed buy,
// and the four-wheel vehicle's real-time factor (the vehicle scene).
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include "shore/bullet/ground_frame.h"
#include "shore/scenes/character_cases.h"
#include "shore/scenes/multibody_cases.h"
#include "shore/scenes/pool_cases.h"
#include "shore/scenes/runner.h"
#include "shore/scenes/soil_cases.h"
#include "shore/scenes/stack_cases.h"
#include "sweep.h"
#include "sweep_util.h"

namespace shore::bench {
namespace {

constexpr double kPoolSide = 3.2;  // m
constexpr double kStandardCell = 0.05, kStandardSubstep = 1.0 / 240;

struct FloatMethod {
  std::string name;
  std::string key;  // figure key stem
  scenes::FloaterShape shape;
  bool vertical_only;
};

scenes::Floater floater_of(const FloatMethod& m) {
  scenes::Floater f;
  f.shape = m.shape;
  f.density_ratio = 0.5;
  if (m.shape == scenes::FloaterShape::box) {
    f.size = btVector3(0.3f, 0.3f, 0.2f);
    f.position = btVector3(0.013f, -0.021f, 0.1f);  // bottom on the surface, off the nodes
  } else {
    f.size = btVector3(0.3f, 0.3f, 0.3f);
    f.position = btVector3(0.013f, -0.021f, 0.15f);
  }
  return f;
}

void floating_sweep(const SweepContext& ctx, SweepResult& out) {
  Table& t =
      out.table("coupling_floating", {"curve", "method", "varied", "cell_m", "nodes", "substep_s", "ms_per_substep",
                                      "coupling_ms_per_substep", "water_ms_per_substep", "s_wall_per_s_sim", "draft_m",
                                      "reference_m", "error_pct", "abs_error_pct"});
  const std::vector<FloatMethod> methods = {
      {"box, vertical-only water", "box_vertical", scenes::FloaterShape::box, true},
      {"box, 3-D water", "box_3d", scenes::FloaterShape::box, false},
      {"sphere, vertical-only water", "sphere_vertical", scenes::FloaterShape::sphere, true}};
  const std::vector<double> cells =
      ctx.quick ? std::vector<double>{0.1, 0.05, 0.025} : std::vector<double>{0.1, 0.05, 0.025, 0.0125};
  const std::vector<double> substeps = ctx.quick
                                           ? std::vector<double>{1.0 / 60, 1.0 / 240, 1.0 / 480}
                                           : std::vector<double>{1.0 / 60, 1.0 / 120, 1.0 / 240, 1.0 / 480, 1.0 / 960};
  for (const FloatMethod& m : methods) {
    const bool swept = m.shape == scenes::FloaterShape::box || !ctx.quick;
    for (const CrossPoint& p : cross(cells, substeps, kStandardCell, kStandardSubstep)) {
      if (!swept && !(same(p.cell, kStandardCell) && same(p.substep, kStandardSubstep))) continue;
      ctx.progress(m.name + ", " + cell_label(p.cell) + ", " + substep_label(p.substep));
      scenes::PoolRun run;
      run.pool.nodes = static_cast<int>(std::lround(kPoolSide / p.cell)) + 1;
      run.pool.cell = p.cell;
      run.pool.damping_time = 1.0;
      run.pool.vertical_only = m.vertical_only;
      run.pool.substep = p.substep;
      run.pool.threads = 1;
      run.seconds = 5.0;
      run.record_every = 1000000;
      const scenes::Floater f = floater_of(m);
      run.floaters = {f};
      const scenes::PoolResult r = scenes::run_pool(run);
      const double reference = scenes::archimedes_draft(f);
      const double draft = r.final_draft.empty() ? NAN : r.final_draft[0];
      const double e = r.nan_count ? NAN : error_pct(draft, reference);
      const double n = double(std::max<std::int64_t>(r.substeps, 1));
      auto row = [&](const std::string& curve, const char* varied) {
        return std::vector<Cell>{curve,
                                 m.name,
                                 varied,
                                 p.cell,
                                 double(run.pool.nodes),
                                 p.substep,
                                 1e3 * r.wall_seconds / n,
                                 1e3 * r.coupling_seconds / n,
                                 1e3 * r.water_seconds / n,
                                 r.wall_seconds / run.seconds,
                                 draft,
                                 reference,
                                 e,
                                 std::abs(e)};
      };
      if (p.on_cell_axis) t.add(row(m.name + " vs water cell", "cell"));
      if (p.on_substep_axis && swept) t.add(row(m.name + " vs substep", "substep"));
      if (same(p.cell, kStandardCell) && same(p.substep, kStandardSubstep)) {
        out.figure("coupling." + m.key + "_draft_error_pct", e, "% vs Archimedes (5 cm water, 1/240 s)");
        out.figure("plugin.water_" + m.key + "_coupling_ms_per_substep", 1e3 * r.coupling_seconds / n,
                   "ms (buoyancy + displacement, 65 x 65 nodes, 1/240 s)");
        out.figure("plugin.water_" + m.key + "_water_ms_per_substep", 1e3 * r.water_seconds / n,
                   "ms (the surface's own steps, 65 x 65 nodes)");
      }
    }
  }
  out.plot({.name = "coupling_floating_time_vs_error",
            .title = "Floating bodies (density 0.5) in a 3.2 m pool: cost against draft error (Archimedes)",
            .table = "coupling_floating",
            .x = "abs_error_pct",
            .y = "s_wall_per_s_sim",
            .series = "curve",
            .x_label = "|draft error|, % of Archimedes",
            .y_label = "wall seconds per simulated second (Bullet + water + coupling)"});
  out.plot({.name = "coupling_floating_plugin_time_vs_error",
            .title = "Floating bodies: coupling time per substep against draft error",
            .table = "coupling_floating",
            .x = "abs_error_pct",
            .y = "coupling_ms_per_substep",
            .series = "curve",
            .x_label = "|draft error|, % of Archimedes",
            .y_label = "coupling ms per substep (buoyancy + displacement)"});
  out.note(
      "Floating: a 0.3 x 0.3 x 0.2 m box and a D 0.3 m sphere at half the water's density, released with their "
      "bottom on the surface of a 3.2 m square pool (0.5 m deep, damping time 1 s, walls vertical-only), 5 s "
      "simulated; draft = mean over the last second of the far-field level minus the body's lowest point, against "
      "Archimedes (box: 0.1 m; sphere: 0.15 m). Water cell swept at 1/240 s, substep at 5 cm; one thread. "
      "coupling_ms is Shore's buoyancy and displacement work, water_ms the surface's own steps.");
}

/// Seconds of each part of Shore's work, and substeps, over a run.
struct PluginTimes {
  double plugin = 0, envelope = 0, terrain = 0, push = 0, whole = 0;
  double substeps = 0;
  explicit PluginTimes(const scenes::RunStats& s)
      : plugin(s.plugin_seconds),
        envelope(s.envelope_seconds),
        terrain(s.terrain_seconds),
        push(s.push_seconds),
        whole(s.wall_seconds),
        substeps(double(s.substeps)) {}
};

/// The towed wheel of the plugin figures: the sand preset at 1 cm and 1/240 s, one thread.
scenes::WheelCase sand_wheel_case() {
  scenes::WheelCase c;
  c.run.terrain.material = terrain::Material::sand();
  c.run.terrain.cell = 0.01;
  c.run.substep = 1.0 / 240;
  c.run.terrain.threads = 1;
  return c;
}

void wheel_plugin_time(const SweepContext& ctx, SweepResult& out) {
  // run_wheel times the whole run: 2 s of load ramp and 0.5 s of settling with the wheel
  // held, then the tow. The held phase is run again alone (the same code path, the same
  // substeps) and subtracted, which leaves the towing phase.
  scenes::WheelCase c = sand_wheel_case();
  // Five towed/held pairs; the pair with the median plugin time is reported, so bursts of
  // load on a shared machine do not decide the figure (with three, one burst in two runs
  // moved it by a third).
  struct Pair {
    scenes::WheelResult towed, held;
    double plugin = 0;
  };
  std::vector<Pair> pairs(5);
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    c.towed = true;
    ctx.progress("towed wheel, 1 cm sand, 1/240 s (plugin time), run " + std::to_string(k + 1) + " of " +
                 std::to_string(pairs.size()));
    pairs[k].towed = scenes::run_wheel(c);
    c.towed = false;
    ctx.progress("the same wheel held (load ramp and settling only), to subtract");
    pairs[k].held = scenes::run_wheel(c);
    pairs[k].plugin = pairs[k].towed.stats.plugin_seconds - pairs[k].held.stats.plugin_seconds;
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.plugin < b.plugin; });
  const Pair& median = pairs[pairs.size() / 2];
  const scenes::WheelResult& towed = median.towed;
  const PluginTimes all(towed.stats), pre(median.held.stats);
  const double n = std::max(1.0, all.substeps - pre.substeps);
  auto per_substep = [&](double PluginTimes::*part) { return 1e3 * (all.*part - pre.*part) / n; };
  const double plugin = per_substep(&PluginTimes::plugin), envelope = per_substep(&PluginTimes::envelope),
               soil = per_substep(&PluginTimes::terrain), push = per_substep(&PluginTimes::push),
               whole = per_substep(&PluginTimes::whole);
  Table& t = out.table("coupling_wheel_plugin", {"part", "tow_ms_per_substep", "whole_run_ms_per_substep"});
  auto whole_run = [&](double seconds) { return 1e3 * seconds / std::max(1.0, all.substeps); };
  t.add({"plugin total", plugin, whole_run(all.plugin)});
  t.add({"envelope", envelope, whole_run(all.envelope)});
  t.add({"terrain step", soil, whole_run(all.terrain)});
  t.add({"tile push + cover", push, whole_run(all.push)});
  t.add({"reaction (rest of plugin)", plugin - envelope - soil - push,
         whole_run(all.plugin - all.envelope - all.terrain - all.push)});
  t.add({"whole step (Bullet + plugin)", whole, whole_run(all.whole)});
  out.figure("plugin.wheel_ms_per_substep", plugin,
             "ms (Shore's own time while towing, one wheel, 1 cm sand, 1/240 s, 1 thread)");
  out.figure("plugin.wheel_envelope_ms_per_substep", envelope, "ms (towing)");
  out.figure("plugin.wheel_terrain_ms_per_substep", soil, "ms (towing)");
  out.figure("plugin.wheel_push_ms_per_substep", push, "ms (towing)");
  out.figure("plugin.wheel_whole_step_ms_per_substep", whole, "ms (towing, Bullet + Shore)");
  out.figure("plugin.wheel_ms_per_substep_whole_run", whole_run(all.plugin), "ms (ramp, settling and tow averaged)");
  out.figure("plugin.wheel_rolling_sinkage_error_pct", error_pct(towed.sinkage, towed.reference_sinkage),
             "% vs Bekker rolling (sand preset, alpha 0.3: rim included)");
  out.target({.key = "plugin.wheel_ms_per_substep",
              .what = "plugin time, one towed wheel on 1 cm sand at 1/240 s",
              .value = plugin,
              .op = "<",
              .threshold = 0.5,
              .unit = "ms/substep"});
  out.target({.key = "plugin.wheel_whole_step_ms_per_substep",
              .what = "whole step (Bullet + Shore), one towed wheel on 1 cm sand at 1/240 s",
              .value = whole,
              .op = "<=",
              .threshold = 0.3,
              .unit = "ms/substep"});
  out.note(
      "Plugin time: one towed wheel (D 0.8 m, b 0.3 m, 4 kN) on 1 cm dry sand (alpha 0.3) at 1/240 s, one "
      "thread: 2 s of load ramp and 0.5 s of settling with the wheel held, then 2 m towed at 1 m/s. The towing "
      "phase's time is the whole run's minus that of the held phase run alone (the same substeps): Shore's own "
      "time per substep (envelope rasterization, soil step, tile cover and push, reaction) and the whole "
      "stepSimulation. The whole-run average is listed beside it. Five towed/held pairs are run; the one with "
      "the median plugin time is reported.");
}

/// The towed wheel's cost and accuracy against the settings that trade one for the other:
/// the erosion pass cap, the contact solver's sweeps, the contact block size, spray, how often
/// the soil steps and whether contacts follow their bodies between soil steps.
/// Each row is the tow phase (towed run minus held run) of the sand wheel at 1 cm, 1/240 s,
/// one thread; the defaults run first and last, so drift of the machine's load shows.
void wheel_cost_settings(const SweepContext& ctx, SweepResult& out) {
  struct Setting {
    const char* name;
    int erosion_passes, iterations, block_columns;
    bool spray;
    double step_interval, follow_drift;
  };
  const terrain::TerrainSettings soil_defaults;
  const bullet::TerrainCouplingSettings coupling_defaults;
  const bullet::TerrainContactSettings& contact_defaults = coupling_defaults.contact;
  const Setting d{
      "defaults", soil_defaults.max_erosion_passes, contact_defaults.iterations,  contact_defaults.block_columns,
      true,       coupling_defaults.step_interval,  contact_defaults.follow_drift};
  // Each row changes the defaults in one respect (or two, named). The defaults before
  // 2026-12-04 were an erosion cap of 8 and 12 solver sweeps, with the soil and the contact
  // every substep (step_interval 0, which follow_drift then does not matter for).
  const std::vector<Setting> settings = {
      d,
      {"former defaults (erosion cap 8, 12 sweeps, soil every substep)", 8, 12, d.block_columns, true, 0.0,
       d.follow_drift},
      {"soil and contact every substep (step_interval 0)", d.erosion_passes, d.iterations, d.block_columns, true, 0.0,
       d.follow_drift},
      {"contact built every substep (follow_drift 0)", d.erosion_passes, d.iterations, d.block_columns, true,
       d.step_interval, 0.0},
      {"erosion cap 8", 8, d.iterations, d.block_columns, true, d.step_interval, d.follow_drift},
      {"twice the solver sweeps", d.erosion_passes, 2 * d.iterations, d.block_columns, true, d.step_interval,
       d.follow_drift},
      {"blocks twice as wide", d.erosion_passes, d.iterations, 2 * d.block_columns, true, d.step_interval,
       d.follow_drift},
      {"spray off", d.erosion_passes, d.iterations, d.block_columns, false, d.step_interval, d.follow_drift},
      {"defaults (again)", d.erosion_passes, d.iterations, d.block_columns, true, d.step_interval, d.follow_drift},
  };
  Table& t =
      out.table("coupling_wheel_settings", {"setting", "erosion_passes", "solver_iterations", "block_columns", "spray",
                                            "step_interval_s", "follow_drift_cells", "tow_whole_ms_per_substep",
                                            "vs_defaults", "sinkage_error_pct", "resistance_error_pct"});
  const int repeats = ctx.quick ? 1 : 3;
  double first_default = 0.0;
  for (const Setting& g : settings) {
    scenes::WheelCase c = sand_wheel_case();
    c.run.terrain.max_erosion_passes = g.erosion_passes;
    c.run.coupling.contact.iterations = g.iterations;
    c.run.coupling.contact.block_columns = g.block_columns;
    c.run.terrain.spray.enabled = g.spray;
    c.run.coupling.step_interval = g.step_interval;
    c.run.coupling.contact.follow_drift = g.follow_drift;
    ctx.progress(std::string("towed wheel cost against settings: ") + g.name);
    std::vector<double> ms;
    scenes::WheelResult towed;
    for (int k = 0; k < repeats; ++k) {
      c.towed = true;
      towed = scenes::run_wheel(c);
      c.towed = false;
      const scenes::WheelResult held = scenes::run_wheel(c);
      const double n = std::max(1.0, double(towed.stats.substeps - held.stats.substeps));
      ms.push_back(1e3 * (towed.stats.wall_seconds - held.stats.wall_seconds) / n);
    }
    std::sort(ms.begin(), ms.end());
    const double median = ms[ms.size() / 2];
    if (first_default == 0.0) first_default = median;
    t.add({g.name, double(g.erosion_passes), double(g.iterations), double(g.block_columns), g.spray ? "on" : "off",
           g.step_interval, g.follow_drift, median, median / first_default,
           error_pct(towed.sinkage, towed.reference_sinkage), error_pct(towed.resistance, towed.reference_resistance)});
  }
  out.note(
      "Wheel cost against settings: the towed sand wheel of plugin.wheel_ms_per_substep (D 0.8 m, b 0.3 m, 4 kN, "
      "1 cm, 1/240 s, one thread), its tow phase's whole step (Bullet + Shore, median of 3 towed/held pairs; 1 in "
      "--quick) with the erosion pass cap (TerrainSettings::max_erosion_passes), the contact solver's sweeps "
      "(TerrainContactSettings::iterations), the contact block (block_columns), spray, the soil's interval "
      "(TerrainCouplingSettings::step_interval) and the contact's following (TerrainContactSettings::follow_drift) "
      "changed from their defaults, and the rolling sinkage and compaction resistance against Bekker's. vs_defaults is "
      "the time over "
      "the first defaults row; the defaults run again last to show the machine's drift.");
}

void vehicle(const SweepContext& ctx, SweepResult& out) {
  ctx.progress("vehicle, 2 cm sand and mud, 1/240 s");
  const scenes::SceneType& scene = *scenes::find_scene("vehicle");
  scenes::Overrides o;  // the scene's defaults: 2 cm soil, 1/240 s, 6 s
  o.threads = 1;
  o.write_files = false;
  const scenes::SceneOptions options = scenes::resolve(scene, o);
  const nlohmann::json m = scenes::run_scene(scene, options, scenes::ProgressMode::quiet).metrics;
  const double realtime = m["realtime_factor"].get<double>(), plugin_ms = m["plugin_ms_per_substep"].get<double>();
  const double wall = m["wall_seconds"].get<double>();
  Table& t = out.table("coupling_vehicle", {"substep_s", "cell_m", "sim_s", "wall_s", "realtime_factor",
                                            "plugin_ms_per_substep", "ms_per_substep", "distance_m", "speed_sand_m_s",
                                            "speed_mud_m_s", "max_sinkage_m", "fallthrough"});
  t.add({options.substep, options.cell, m["sim_seconds"].get<double>(), wall, realtime, plugin_ms,
         1e3 * wall / m["substeps"].get<double>(), m["distance_m"].get<double>(),
         m["mean_speed_sand_mps"].get<double>(), m["mean_speed_mud_mps"].get<double>(),
         m["max_sinkage_m"].get<double>(), m["fallthrough_count"].get<double>()});
  out.figure("plugin.vehicle_realtime_factor", realtime,
             "x real time (4 wheels, 2 cm sand + mud, 240 substeps/s, 1 thread)");
  out.figure("plugin.vehicle_plugin_ms_per_substep", plugin_ms, "ms");
  out.target({.key = "plugin.vehicle_realtime_factor",
              .what = "four-wheel vehicle over sand and mud, 240 substeps/s",
              .value = realtime,
              .op = ">=",
              .threshold = 5.0,
              .unit = "x real time"});
  out.note(
      "Vehicle (the vehicle scene): chassis 400 kg on four motorised cylinder wheels (D 0.6 m) driving from rigid "
      "ground over 3 tiles of sand and 3 of mud at 2 cm, 240 substeps per second, 6 s simulated, one thread; "
      "real-time factor = simulated / wall seconds of the whole stepSimulation.");
}

void rally(const SweepContext& ctx, SweepResult& out) {
  ctx.progress("rally, a stock raycast car, 1/60 s, 3 runs");
  const scenes::SceneType& scene = *scenes::find_scene("rally");
  scenes::Overrides o;  // the scene's defaults: 4 cm land, 1/60 s, 14 s
  o.threads = 1;
  o.write_files = false;
  // The least wall time of three runs: a shared machine only ever slows a run down, so the
  // fastest is the one least disturbed (single runs of this scene differ by 10 % here).
  Table& t = out.table("coupling_rally", {"run", "sim_s", "wall_s", "realtime_factor", "distance_m", "deepest_rut_m"});
  double realtime = 0.0;
  for (int run = 0; run < 3; ++run) {
    const nlohmann::json m = scenes::run_scene(scene, scenes::resolve(scene, o), scenes::ProgressMode::quiet).metrics;
    const double run_realtime = m["realtime_factor"].get<double>();
    realtime = std::max(realtime, run_realtime);
    t.add({double(run), m["sim_seconds"].get<double>(), m["wall_seconds"].get<double>(), run_realtime,
           m["distance_m"].get<double>(), m["deepest_rut_m"].get<double>()});
  }
  out.figure("scenes.rally_realtime_factor", realtime, "x real time (a raycast car, 60 steps/s, 1 thread)");
  out.target({.key = "scenes.rally_realtime_factor",
              .what = "rally: a stock raycast car over sand, mud and a ford at 1/60 s steps",
              .value = realtime,
              .op = ">=",
              .threshold = 20.0,
              .unit = "x real time"});
  out.note(
      "Rally (the rally scene): a stock btRaycastVehicle (800 kg) driven 14 s up a valley of 4 cm sand with painted "
      "mud and a ford (its chassis in the water coupling), 60 steps per second, one thread; real-time factor = "
      "simulated / wall seconds of the whole step, the fastest of 3 runs.");
}

/// A stock character controller over hilly sand with a line of 3 cm footprints, at 1 and 2 cm
/// columns, with its tiles' contact stride 1, 2 and 4: the capsule's cost per step against
/// how far its path and its height over the soil move from those on every column.
void character_stride(const SweepContext& ctx, SweepResult& out) {
  ctx.progress("character controller: contact stride 1, 2, 4 at 1 and 2 cm");
  Table& t = out.table("coupling_character_stride", {"cell_m", "stride", "ms_per_step", "speedup", "path_error_m",
                                                     "gap_min_m", "gap_mean_m", "gap_mean_change_m"});
  for (const double cell : {0.01, 0.02}) {
    constexpr std::array<int, 3> kStrides = {1, 2, 4};
    std::vector<scenes::CharacterWalkResult> runs;
    for (const int stride : kStrides)
      runs.push_back(scenes::run_character_walk({.cell = cell, .contact_stride = stride}));
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const double speedup = runs[0].wall_ms_per_step / runs[k].wall_ms_per_step;
      const double path = scenes::track_distance(runs[k].track, runs[0].track);
      const double gap_change = runs[k].gap_mean - runs[0].gap_mean;
      const int stride = kStrides[k];
      t.add({cell, double(stride), runs[k].wall_ms_per_step, speedup, path, runs[k].gap_min, runs[k].gap_mean,
             gap_change});
      const std::string at = std::to_string(int(std::lround(cell * 100))) + "cm";
      if (stride == 1)
        out.figure("plugin.character_ms_per_step_" + at, runs[k].wall_ms_per_step,
                   "ms per 1/120 s step, contact stride 1 (every column)");
      if (stride == 2) {
        out.figure("plugin.character_stride2_speedup_" + at, speedup, "x, stride 2 over stride 1, same run");
        out.figure("plugin.character_stride2_path_error_" + at, path,
                   "m, largest distance from the path on every column");
      }
    }
  }
  out.note(
      "Character (run_character_walk): a stock btKinematicCharacterController (capsule r 0.25 m, 1.7 m tall) walks "
      "4 s at 1.3 m/s over hilly sand with a line of 3 cm deep prints, 1/120 s steps, one thread. Its tiles give "
      "Bullet's sweeps and contacts one triangle pair per stride x stride columns "
      "(TerrainTilesSettings::contact_stride); speedup and errors against stride 1 in the same run.");
}

/// The rover scene at its defaults: a six-wheeled btMultiBody over a sand dune and through a
/// pool, one thread.
void rover(const SweepContext& ctx, SweepResult& out) {
  ctx.progress("rover, a six-wheeled btMultiBody, 1/60 s");
  const scenes::SceneType& scene = *scenes::find_scene("rover");
  scenes::Overrides o;  // the scene's defaults: 4 cm land, 1/60 s, 26 s
  o.threads = 1;
  o.write_files = false;
  const nlohmann::json m = scenes::run_scene(scene, scenes::resolve(scene, o), scenes::ProgressMode::quiet).metrics;
  const double realtime = m["realtime_factor"].get<double>();
  Table& t = out.table("coupling_rover", {"sim_s", "wall_s", "realtime_factor", "distance_m", "climb_drawbar_pull_N",
                                          "climb_slip", "wade_slip"});
  t.add({m["sim_seconds"].get<double>(), m["wall_seconds"].get<double>(), realtime, m["distance_m"].get<double>(),
         m.value("climb_drawbar_pull_N", 0.0), m.value("climb_slip", 0.0), m.value("wade_slip", 0.0)});
  out.figure("scenes.rover_realtime_factor", realtime,
             "x real time (a six-wheeled multibody rover, 60 steps/s, 1 thread)");
  out.target({.key = "scenes.rover_realtime_factor",
              .what = "rover: a six-wheeled btMultiBody over a sand dune and through a pool at 1/60 s steps",
              .value = realtime,
              .op = ">=",
              .threshold = 10.0,
              .unit = "x real time"});
  out.note(
      "Rover (the rover scene): a btMultiBody of a 120 kg chassis and six 6 kg wheels (D 0.6 m, b 0.25 m) on "
      "revolute joints driven by joint motors, every wheel and the chassis links of the terrain coupling, the "
      "chassis also of the water coupling; 26 s over a 4 cm sand dune (15 % grade) and through a pool, 60 steps "
      "per second, one thread; real-time factor = simulated / wall seconds of the whole step.");
}

/// btMultiBody links against the references the rigid bodies meet: the validation matrix's
/// plate as a multibody's base against Bekker, and the towed sand wheel on a revolute joint
/// against the rigid-body wheel of the same case, Shore's time of each run side by side.
void multibody_links(const SweepContext& ctx, SweepResult& out) {
  ctx.progress("multibody plate (0.2 m, 30 kPa, sandy loam at 22 %) against Bekker");
  const scenes::MultiBodyPlateResult plate = scenes::run_multibody_plate({});
  const double plate_error = error_pct(plate.sinkage, plate.bekker);
  Table& t = out.table("coupling_multibody", {"case", "value", "reference", "error_pct"});
  t.add({"plate sinkage (m) vs Bekker", plate.sinkage, plate.bekker, plate_error});
  out.figure("plugin.multibody_plate_error_pct", plate_error, "% vs Bekker (multibody base plate, 0.2 m, 30 kPa)");
  out.target({.key = "plugin.multibody_plate_error_pct",
              .what = "a multibody's base plate (0.2 m, 30 kPa, sandy loam) at Bekker's sinkage",
              .value = std::abs(plate_error),
              .op = "<=",
              .threshold = 5.0,
              .unit = "|% error|"});
  // The rigid wheel and the multibody wheel alternated; the median of the ratio of each
  // pair's Shore time, so load bursts on a shared machine do not decide it.
  scenes::WheelCase c = sand_wheel_case();
  c.towed = true;
  Table& w = out.table("coupling_multibody_wheel", {"pair", "rigid_plugin_s", "multibody_plugin_s", "ratio",
                                                    "rigid_sinkage_m", "multibody_sinkage_m"});
  std::vector<double> ratios;
  const int pairs = ctx.quick ? 3 : 5;
  for (int k = 0; k < pairs; ++k) {
    ctx.progress("towed sand wheel, rigid body then multibody link, pair " + std::to_string(k + 1) + " of " +
                 std::to_string(pairs));
    const scenes::WheelResult rigid = scenes::run_wheel(c);
    const scenes::MultiBodyWheelResult link = scenes::run_multibody_wheel(c);
    const double ratio = link.stats.plugin_seconds / std::max(rigid.stats.plugin_seconds, 1e-9);
    ratios.push_back(ratio);
    w.add({double(k), rigid.stats.plugin_seconds, link.stats.plugin_seconds, ratio, rigid.sinkage, link.sinkage});
  }
  std::sort(ratios.begin(), ratios.end());
  const double ratio = ratios[ratios.size() / 2];
  out.figure("plugin.multibody_wheel_cost_ratio", ratio,
             "x the rigid-body wheel's Shore time (towed sand wheel, median of adjacent pairs)");
  out.target({.key = "plugin.multibody_wheel_cost_ratio",
              .what = "a multibody wheel costs Shore what the rigid-body wheel costs on the same soil",
              .value = ratio,
              .op = "<=",
              .threshold = 1.10,
              .unit = "x the rigid-body wheel"});
  out.note(
      "Multibody links: the validation matrix's plate (0.2 m, 30 kPa on sandy loam at 22 %, weight eased in over "
      "3 s) as a free multibody's base, its sinkage against Bekker's; the towed sand wheel of "
      "plugin.wheel_ms_per_substep (D 0.8 m, b 0.3 m, 4 kN, 1 cm, 1/240 s, one thread) as a rigid body and as the "
      "revolute link of a carriage-hanger-wheel multibody, whole runs (press and tow) alternated; the ratio is the "
      "median over pairs of the link's Shore time (envelopes, soil, push, reaction) over the rigid body's.");
}

/// The drag of a towed box and ball against the law 1/2 rho C_d A v^2 + rho k A v, across
/// the samples per cell of the displacement (the drag must not depend on them), and a dense
/// ball's terminal velocity against the drag balance.
void drag_sweep(const SweepContext& ctx, SweepResult& out) {
  Table& t = out.table("coupling_drag", {"case", "samples_per_cell", "waves", "drag_N", "law_N", "error_pct"});
  const auto tow = [](scenes::FloaterShape shape, int samples, bool waves) {
    scenes::TowRun run;
    run.pool.nodes = 128;
    run.pool.nodes_y = 64;
    run.pool.damping_time = 1.0;
    run.pool.fluid.samples_per_cell = samples;
    run.floater.shape = shape;
    run.floater.size = shape == scenes::FloaterShape::box ? btVector3(0.3f, 0.3f, 0.2f) : btVector3(0.2f, 0.2f, 0.2f);
    run.floater.density_ratio = 0.5;
    run.floater.position = btVector3(-2.5f, 0.013f, 0.0f);
    run.disturb = waves;
    return scenes::run_tow(run);
  };
  double drag2 = 0.0, drag8 = 0.0;
  for (int samples : {1, 2, 4, 8}) {
    ctx.progress("towed box at 1 m/s, " + std::to_string(samples) + " samples per cell");
    const scenes::TowResult r = tow(scenes::FloaterShape::box, samples, true);
    t.add({"box 0.3 m, draft 0.1 m", double(samples), "yes", r.drag, r.reference, error_pct(r.drag, r.reference)});
    if (samples == 2) drag2 = r.drag;
    if (samples == 8) drag8 = r.drag;
    if (samples == 2)
      out.figure("coupling.towed_box_drag_error_pct", error_pct(r.drag, r.reference), "% vs the law (in its waves)");
  }
  for (bool waves : {false, true}) {
    ctx.progress(std::string("towed ball at 1 m/s") + (waves ? ", in its waves" : ", no waves"));
    const scenes::TowResult r = tow(scenes::FloaterShape::sphere, 2, waves);
    t.add({"ball D 0.2 m, half submerged", 2.0, waves ? "yes" : "no", r.drag, r.reference,
           error_pct(r.drag, r.reference)});
  }
  const double ratio = drag8 / drag2;
  out.figure("coupling.drag_ratio_8_vs_2_samples", ratio, "x (towed box drag at 8 vs 2 samples per cell)");
  out.target({.key = "coupling.drag_ratio_8_vs_2_samples",
              .what = "towed box drag at 8 samples per cell over 2 (within 5 %)",
              .value = std::abs(ratio - 1.0),
              .op = "<=",
              .threshold = 0.05,
              .unit = "|ratio - 1|"});
  ctx.progress("dense ball sinking through 3 m");
  scenes::SinkRun sink;
  sink.pool.depth = 3.0;
  sink.pool.nodes = 32;
  sink.pool.cell = 0.1;
  sink.seconds = 8.0;
  const scenes::SinkResult s = scenes::run_sink(sink);
  out.figure("coupling.terminal_velocity_error_pct", error_pct(s.terminal, s.reference), "% vs the drag balance");
  t.add({"ball D 0.1 m, density 1.5, terminal velocity (m/s)", 2.0, "no", s.terminal, s.reference,
         error_pct(s.terminal, s.reference)});
  out.note(
      "Drag: a box 0.3 m wide at its 0.1 m draft and a ball of 0.2 m half submerged, towed kinematically at 1 m/s "
      "through 6.4 x 3.2 m of still water (5 cm, 1/240 s); the water's force along the tow over the last of 2.5 s "
      "against 1/2 rho C_d A v^2 + rho k A v (C_d 1, k 0.2 m/s, A the frontal area below the level: 0.03 m^2 and "
      "0.0157 m^2), with the body's own waves (the bow wave adds a few per cent) and without. drag_ratio_8_vs_2 "
      "is the box's drag at 8 samples per cell over 2. Terminal velocity: a ball of 0.1 m and density 1.5 sinking "
      "through 3 m, mean speed between 1.2 and 2.4 m down, against (rho_b - rho) V g = 1/2 rho C_d A v^2 + rho k A v.");
}

/// A Y-up world against the same Z-up one: the towed wheel (whose motion the frame does not
/// change beyond rounding; a scene of tumbling bodies would time another motion) run whole
/// in each, alternated, the median of the ratio of adjacent runs (robust to drift).
void ground_frame_cost(const SweepContext& ctx, SweepResult& out) {
  ctx.progress("towed wheel in a Z-up and a Y-up world");
  auto wall = [](const bullet::GroundFrame& frame) {
    scenes::WheelCase c;
    c.towed = true;
    c.run.coupling.frame = frame;
    return scenes::run_wheel(c).stats.wall_seconds;
  };
  Table& t = out.table("coupling_ground_frame", {"pair", "z_up_wall_s", "y_up_wall_s", "y_up_over_z_up"});
  std::vector<double> ratios;
  const int pairs = ctx.quick ? 3 : 7;
  for (int k = 0; k < pairs; ++k) {
    const double z = wall(bullet::GroundFrame::z_up()), y = wall(bullet::GroundFrame::y_up());
    ratios.push_back(y / z);
    t.add({double(k), z, y, y / z});
  }
  std::sort(ratios.begin(), ratios.end());
  const double ratio = ratios[ratios.size() / 2];
  out.figure("plugin.y_up_cost_ratio", ratio, "Y-up over Z-up wall time, the towed wheel (median of adjacent pairs)");
  out.target({.key = "plugin.y_up_cost_ratio",
              .what = "a Y-up world costs what the same Z-up world costs",
              .value = ratio,
              .op = "<=",
              .threshold = 1.03,
              .unit = "x the Z-up run"});
  out.note(
      "Ground frame: the towed sand wheel of plugin.wheel_ms_per_substep (D 0.8 m, b 0.3 m, 4 kN, 1 cm, 1/240 s, "
      "one thread) in a Z-up world and in a Y-up one (GroundFrame::y_up()), whole runs (press and tow) alternated; "
      "the ratio is the median over pairs of the Y-up run's wall time over the Z-up run's before it.");
}

/// Bodies on bodies: a stack of boxes on each preset soil, the bottom box against Bekker's
/// plate released under the whole stack's weight, at the README's 1/240 s substeps and at
/// Bullet's default 1/60 s ones (where the soil's push, made after Bullet's own solve, meets
/// the stack's weight a substep late: docs/terrain.md, "Bodies on bodies").
void stacks(const SweepContext& ctx, SweepResult& out) {
  Table& t = out.table("coupling_stack", {"soil", "boxes", "substep_s", "sinkage_m", "reference_m", "ratio",
                                          "overlap_m", "late_speed_m_s", "rescues"});
  // The worst error of each substep: the 3-box stack farthest from Bekker's value, in %.
  double worst_240 = 0.0, worst_60 = 0.0;
  for (const char* soil : {"sand", "mud", "snow"})
    for (int boxes : {1, 3})
      for (double substep : {1.0 / 240, 1.0 / 60}) {
        ctx.progress(std::string("stack of ") + std::to_string(boxes) + " on " + soil);
        scenes::StackCase c;
        c.run.terrain.material = terrain::Material::preset(soil);
        c.run.substep = substep;
        c.boxes = boxes;
        const scenes::StackResult r = scenes::run_stack(c);
        const double error = error_pct(r.sinkage, r.reference);
        t.add({std::string(soil), double(boxes), substep, r.sinkage, r.reference, r.sinkage / r.reference, r.overlap,
               r.late_speed, double(r.rescues)});
        double& worst = substep > 1.0 / 100 ? worst_60 : worst_240;
        if (boxes > 1 && std::abs(error) > std::abs(worst)) worst = error;
      }
  for (const auto& [key, value, substep] : {std::tuple{"plugin.stack_sinkage_error_pct_240hz", worst_240, "1/240"},
                                            std::tuple{"plugin.stack_sinkage_error_pct_60hz", worst_60, "1/60"}}) {
    out.figure(key, value,
               std::string("% vs Bekker's released plate (bottom of 3 stacked boxes, worst of sand, mud, snow; ") +
                   substep + " s substeps)");
    out.target({.key = key,
                .what = std::string("a stack of 3 boxes at ") + substep +
                        " s substeps: the bottom box sinks as Bekker's plate released under the stack",
                .value = std::abs(value),
                .op = "<=",
                .threshold = 10.0,
                .unit = "|% error|"});
  }
  out.note(
      "Stacks (scenes::run_stack): 1 or 3 boxes of 200 kg, 0.5 x 0.5 x 0.2 m, set down touching at rest on sand, "
      "mud and snow on 4 cm columns, 6 s; the bottom box's sinkage over Bekker's rigid-plastic plate released "
      "under the whole weight (terrain::bekker::plate_sinkage_released); overlap: the deepest any box reached "
      "into the one below.");
}

void run(const SweepContext& ctx, SweepResult& out) {
  ground_frame_cost(ctx, out);
  drag_sweep(ctx, out);
  wheel_plugin_time(ctx, out);
  wheel_cost_settings(ctx, out);
  vehicle(ctx, out);
  rally(ctx, out);
  character_stride(ctx, out);
  rover(ctx, out);
  multibody_links(ctx, out);
  stacks(ctx, out);
  floating_sweep(ctx, out);
}

const SweepRegistrar kRegistered{Sweep{
    .name = "coupling",
    .description = "Bullet plugin: floating draft vs Archimedes across water cell and substep; wheel and vehicle cost",
    .run = run,
}};

}  // namespace
}  // namespace shore::bench
