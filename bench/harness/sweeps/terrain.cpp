// terrain: the soil's speed against its error. Every case runs through Bullet and the
// plugin (shore::scenes, soil_cases.h) and is compared with a reference outside the code:
// Bekker's plate and wheel sinkages (shore/terrain/bekker.h), the cap and prism volumes of
// an imprint, the energy balance of a dropped sphere (sphere_drop_reference_depth). Cell size is swept at the standard
// substep (1/240 s) and the substep at the standard cell (1 cm).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <btBulletDynamicsCommon.h>

#include "shore/bullet/terrain_coupling.h"
#include "shore/scenes/soil_cases.h"
#include "shore/scenes/terrain_step_cases.h"
#include "shore/scenes/world.h"
#include "sweep.h"
#include "sweep_util.h"

namespace shore::bench {
namespace {

constexpr double kStandardCell = 0.01, kStandardSubstep = 1.0 / 240;

struct Axes {
  std::vector<double> cells, substeps;
};

Axes axes(const SweepContext& ctx) {
  if (ctx.quick) return {{0.04, 0.02, 0.01}, {1.0 / 60, 1.0 / 240, 1.0 / 480}};
  return {{0.04, 0.02, 0.01, 0.005}, {1.0 / 60, 1.0 / 120, 1.0 / 240, 1.0 / 480, 1.0 / 960}};
}

/// Adds one row per axis the point lies on (the standard point appears in both curves).
template <class MakeRow>
void add_rows(Table& t, const std::string& method, const CrossPoint& p, MakeRow&& row) {
  if (p.on_cell_axis) t.add(row(method + " vs cell", "cell"));
  if (p.on_substep_axis) t.add(row(method + " vs substep", "substep"));
}

scenes::SoilRun soil_run(const terrain::Material& m, const CrossPoint& p) {
  scenes::SoilRun r;
  r.terrain.material = m;
  r.terrain.cell = p.cell;
  r.substep = p.substep;
  r.terrain.threads = 1;
  return r;
}

std::string where(const CrossPoint& p) { return cell_label(p.cell) + ", " + substep_label(p.substep); }

// ---- plate ------------------------------------------------------------------------------
void plate_sweep(const SweepContext& ctx, SweepResult& out) {
  Table& t = out.table("terrain_plate",
                       {"curve", "method", "varied", "cell_m", "substep_s", "ms_per_substep", "plugin_ms_per_substep",
                        "s_wall_per_s_sim", "sinkage_m", "reference_m", "error_pct", "abs_error_pct"});
  const Axes a = axes(ctx);
  for (const bool ramped : {false, true}) {
    const std::string method = ramped ? "plate ramped 2 s" : "plate released";
    for (const CrossPoint& p : cross(a.cells, a.substeps, kStandardCell, kStandardSubstep)) {
      ctx.progress(method + ", " + where(p));
      scenes::PlateCase c;
      c.run = soil_run(terrain::Material::sand(), p);
      c.ramp_seconds = ramped ? 2.0 : 0.0;
      c.settle_seconds = ramped ? 0.5 : 1.0;
      const scenes::PlateResult r = scenes::run_plate(c);
      const double e = error_pct(r.sinkage, r.reference);
      add_rows(t, method, p, [&](const std::string& curve, const char* varied) {
        return std::vector<Cell>{curve,
                                 method,
                                 varied,
                                 p.cell,
                                 p.substep,
                                 r.stats.ms_per_substep(),
                                 r.stats.plugin_ms_per_substep(),
                                 r.stats.ms_per_substep() * 1e-3 / p.substep,
                                 r.sinkage,
                                 r.reference,
                                 e,
                                 std::abs(e)};
      });
      if (same(p.cell, kStandardCell) && same(p.substep, kStandardSubstep)) {
        out.figure(ramped ? "terrain.plate_ramped_error_pct" : "terrain.plate_released_error_pct", e,
                   "% vs Bekker (1 cm, 1/240 s)");
        out.figure(ramped ? "terrain.plate_ramped_reference_mm" : "terrain.plate_released_reference_mm",
                   r.reference * 1e3, "mm");
      }
    }
  }
  out.plot({.name = "terrain_plate_time_vs_error",
            .title = "Plate 0.3 m, 50 kPa, dry sand: cost against sinkage error (Bekker)",
            .table = "terrain_plate",
            .x = "abs_error_pct",
            .y = "s_wall_per_s_sim",
            .series = "curve",
            .x_label = "|sinkage error|, % of Bekker",
            .y_label = "wall seconds per simulated second"});
  out.note(
      "Plate: square 0.3 m box, 50 kPa, dry sand (n 1.1), through Bullet and the plugin. Released at rest "
      "(reference: rigid-plastic overshoot, (n+1)^(1/n) times Bekker's quasi-static sinkage) or with its weight "
      "ramped in over 2 s (reference: Bekker's quasi-static sinkage). Cell size swept at 1/240 s, substep at 1 cm; "
      "one thread.");
}

// ---- wheel ------------------------------------------------------------------------------
struct WheelMethod {
  std::string name;
  terrain::Material material;
  bool towed;
};

void wheel_sweep(const SweepContext& ctx, SweepResult& out) {
  Table& t =
      out.table("terrain_wheel", {"curve", "method", "varied", "cell_m", "substep_s", "ms_per_substep",
                                  "plugin_ms_per_substep", "envelope_ms_per_substep", "terrain_ms_per_substep",
                                  "push_ms_per_substep", "s_wall_per_s_sim", "sinkage_m", "reference_m", "error_pct",
                                  "abs_error_pct", "resistance_n", "reference_resistance_n", "resistance_error_pct"});
  terrain::Material alpha0 = terrain::Material::sand();
  alpha0.alpha = 0.0;
  const std::vector<WheelMethod> methods = {{"wheel static", alpha0, false},
                                            {"wheel rolling alpha 0", alpha0, true},
                                            {"wheel rolling sand alpha 0.3", terrain::Material::sand(), true}};
  const Axes a = axes(ctx);
  for (const WheelMethod& m : methods) {
    for (const CrossPoint& p : cross(a.cells, a.substeps, kStandardCell, kStandardSubstep)) {
      ctx.progress(m.name + ", " + where(p));
      scenes::WheelCase c;
      c.run = soil_run(m.material, p);
      c.towed = m.towed;
      const scenes::WheelResult r = scenes::run_wheel(c);
      const double e = error_pct(r.sinkage, r.reference_sinkage);
      const double re = m.towed ? error_pct(r.resistance, r.reference_resistance) : NAN;
      const double n = double(std::max<std::int64_t>(r.stats.substeps, 1));
      add_rows(t, m.name, p, [&](const std::string& curve, const char* varied) {
        return std::vector<Cell>{curve,
                                 m.name,
                                 varied,
                                 p.cell,
                                 p.substep,
                                 r.stats.ms_per_substep(),
                                 r.stats.plugin_ms_per_substep(),
                                 1e3 * r.stats.envelope_seconds / n,
                                 1e3 * r.stats.terrain_seconds / n,
                                 1e3 * r.stats.push_seconds / n,
                                 r.stats.ms_per_substep() * 1e-3 / p.substep,
                                 r.sinkage,
                                 r.reference_sinkage,
                                 e,
                                 std::abs(e),
                                 m.towed ? r.resistance : NAN,
                                 m.towed ? r.reference_resistance : NAN,
                                 re};
      });
      if (same(p.cell, kStandardCell) && same(p.substep, kStandardSubstep)) {
        const std::string key = m.name == "wheel static"            ? "wheel_static"
                                : m.name == "wheel rolling alpha 0" ? "wheel_rolling_alpha0"
                                                                    : "wheel_rolling_sand";
        out.figure("terrain." + key + "_sinkage_error_pct", e, "% vs Bekker (1 cm, 1/240 s)");
        out.figure("terrain." + key + "_reference_mm", r.reference_sinkage * 1e3, "mm");
        if (m.towed) out.figure("terrain." + key + "_resistance_error_pct", re, "% vs Bekker compaction resistance");
        out.figure("terrain." + key + "_s_per_sim_s", r.stats.ms_per_substep() * 1e-3 / p.substep,
                   "s wall per s simulated (1 cm, 1/240 s, Bullet + Shore)");
      }
    }
  }
  out.plot({.name = "terrain_wheel_time_vs_error",
            .title = "Rigid wheel D 0.8 m, 4 kN, dry sand: cost against sinkage error (Bekker)",
            .table = "terrain_wheel",
            .x = "abs_error_pct",
            .y = "s_wall_per_s_sim",
            .series = "curve",
            .x_label = "|sinkage error|, % of Bekker",
            .y_label = "wall seconds per simulated second"});
  out.plot({.name = "terrain_wheel_error_vs_cell",
            .title = "Rigid wheel: sinkage error against cell size (1/240 s)",
            .table = "terrain_wheel",
            .x = "cell_m",
            .y = "abs_error_pct",
            .series = "curve",
            .x_label = "cell, m",
            .y_label = "|sinkage error|, % of Bekker"});
  out.note(
      "Wheel: rigid cylinder D 0.8 m, b 0.3 m, 4 kN, dry sand. Static: load ramped in over 2 s with the wheel held "
      "(reference: Bekker with both halves bearing, 47.5 mm). Rolling: then towed 2 m at 1 m/s, sinkage and towing "
      "force averaged over the second metre (reference: Bekker's rolling wheel, front half bearing, 73.6 mm, and "
      "the compaction resistance). alpha 0 is pure compaction, the case Bekker describes; the sand preset "
      "(alpha 0.3) pushes 30 % of the displaced soil into a rim ahead of and beside the wheel, which it must climb: "
      "its departure from Bekker is the rim's effect, not a numerical error. Static and alpha 0 cases use the "
      "alpha 0 material. One thread. Curves 'vs cell' at 1/240 s, 'vs substep' at 1 cm.");
}

// ---- imprint volume ----------------------------------------------------------------------
/// A kinematic body lowered into snow (alpha 0: all compaction) to a given depth through the
/// plugin; returns the volume the ground lost and the plugin's time per substep.
struct ImprintRun {
  double lowered_m3 = 0.0;
  double ms_per_substep = 0.0;
};

ImprintRun press_kinematic(std::unique_ptr<btCollisionShape> shape, double bottom_offset, double depth, double cell) {
  terrain::TerrainSettings s;
  s.cell = cell;
  s.material = terrain::Material::snow();
  s.material.alpha = 0.0;
  s.threads = 1;
  terrain::Terrain soil(s);
  scenes::World world;
  bullet::TerrainCoupling ground(world.world(), soil);
  // Off the column lattice by a fraction of a cell, so no edge passes exactly through columns.
  const double x0 = 0.0031, y0 = 0.0017;
  btRigidBody* body =
      world.add_body(std::move(shape), 0.0, btVector3(btScalar(x0), btScalar(y0), btScalar(bottom_offset)));
  body->setCollisionFlags(body->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
  body->setActivationState(DISABLE_DEACTIVATION);
  ground.add_body(body);
  const double h = 1.0 / 240;
  const int lower_steps = 24, hold_steps = 4;
  double plugin_s = 0.0;
  for (int k = 1; k <= lower_steps + hold_steps; ++k) {
    const double z = bottom_offset - depth * std::min(1.0, double(k) / lower_steps);
    btTransform pose;
    pose.setIdentity();
    pose.setOrigin(btVector3(btScalar(x0), btScalar(y0), btScalar(z)));
    body->getMotionState()->setWorldTransform(pose);
    body->setWorldTransform(pose);
    world.step(h);
    const bullet::TerrainCouplingStats& g = ground.stats();
    plugin_s += g.envelope_seconds + g.terrain_seconds + g.push_seconds + g.reaction_seconds;
  }
  ImprintRun r;
  r.ms_per_substep = 1e3 * plugin_s / (lower_steps + hold_steps);
  const double reach = 0.5;  // m, larger than any body here
  const std::int64_t i0 = soil.column_i(x0 - reach), i1 = soil.column_i(x0 + reach);
  const std::int64_t j0 = soil.column_j(y0 - reach), j1 = soil.column_j(y0 + reach);
  for (std::int64_t j = j0; j <= j1; ++j)
    for (std::int64_t i = i0; i <= i1; ++i) r.lowered_m3 += std::max(0.0, soil.base_height(i, j) - soil.height(i, j));
  r.lowered_m3 *= cell * cell;
  return r;
}

void imprint_sweep(const SweepContext& ctx, SweepResult& out) {
  Table& t = out.table("terrain_imprint", {"method", "cell_m", "plugin_ms_per_substep", "volume_m3", "reference_m3",
                                           "error_pct", "abs_error_pct"});
  const double R = 0.15, depth = 0.05;          // sphere D 0.3 m pressed 5 cm
  const double bx = 0.15, by = 0.1, bz = 0.05;  // box 0.3 x 0.2 x 0.1 m (half extents)
  const double cap = std::numbers::pi * depth * depth * (R - depth / 3.0);
  const double prism = 4.0 * bx * by * depth;
  for (double cell : axes(ctx).cells) {
    ctx.progress("imprint, " + cell_label(cell));
    const ImprintRun s = press_kinematic(std::make_unique<btSphereShape>(btScalar(R)), R, depth, cell);
    const ImprintRun b = press_kinematic(
        std::make_unique<btBoxShape>(btVector3(btScalar(bx), btScalar(by), btScalar(bz))), bz, depth, cell);
    const double es = error_pct(s.lowered_m3, cap), eb = error_pct(b.lowered_m3, prism);
    t.add({"sphere D 0.3 m, 5 cm", cell, s.ms_per_substep, s.lowered_m3, cap, es, std::abs(es)});
    t.add({"box 0.3 x 0.2 m, 5 cm", cell, b.ms_per_substep, b.lowered_m3, prism, eb, std::abs(eb)});
    if (same(cell, kStandardCell)) {
      out.figure("terrain.imprint_sphere_volume_error_pct", es, "% vs spherical cap (1 cm)");
      out.figure("terrain.imprint_box_volume_error_pct", eb, "% vs prism (1 cm)");
    }
  }
  out.plot({.name = "terrain_imprint_time_vs_error",
            .title = "Kinematic imprint in snow (alpha 0): plugin time against volume error",
            .table = "terrain_imprint",
            .x = "abs_error_pct",
            .y = "plugin_ms_per_substep",
            .series = "method",
            .x_label = "|imprint volume error|, % of cap / prism",
            .y_label = "plugin ms per substep (envelope + soil + tiles)"});
  out.note(
      "Imprint: a kinematic sphere (D 0.3 m) and box (0.3 x 0.2 m footprint) lowered 5 cm into snow with alpha 0 "
      "(all compaction) over 24 substeps of 1/240 s through the plugin (envelope rasterization, soil step, tile "
      "update); the volume the ground lost against the spherical cap pi z^2 (R - z/3) and the prism. Bodies sit off "
      "the column lattice by a fraction of a cell; the error is the footprint's discretisation.");
}

// ---- sphere drop -----------------------------------------------------------------------
void sphere_drop_sweep(const SweepContext& ctx, SweepResult& out) {
  Table& t =
      out.table("terrain_sphere_drop", {"method", "cell_m", "substep_s", "ms_per_substep", "plugin_ms_per_substep",
                                        "s_wall_per_s_sim", "depth_m", "reference_m", "error_pct", "abs_error_pct"});
  for (double h : axes(ctx).substeps) {
    ctx.progress("sphere drop, " + substep_label(h));
    scenes::SphereDropCase c;
    c.run = soil_run(terrain::Material::sand(), {kStandardCell, h});
    const scenes::SphereDropResult r = scenes::run_sphere_drop(c);
    const double e = error_pct(r.depth, r.reference);
    t.add({"sphere drop, 1 cm sand", kStandardCell, h, r.stats.ms_per_substep(), r.stats.plugin_ms_per_substep(),
           r.stats.ms_per_substep() * 1e-3 / h, r.depth, r.reference, e, std::abs(e)});
    if (same(h, kStandardSubstep))
      out.figure("terrain.sphere_drop_depth_error_pct", e, "% vs energy balance (1/240 s)");
  }
  out.plot({.name = "terrain_sphere_drop_time_vs_error",
            .title = "Sphere dropped into sand: cost against crater depth error",
            .table = "terrain_sphere_drop",
            .x = "abs_error_pct",
            .y = "s_wall_per_s_sim",
            .series = "method",
            .x_label = "|crater depth error|, % of the energy balance",
            .y_label = "wall seconds per simulated second"});
  out.note(
      "Sphere drop: D 0.2 m, 10 kg, released 1 m above dry sand at 1 cm, 1.5 s simulated; the reference is the "
      "depth at which m g (height + z) equals the plastic work of Bekker columns under a spherical cap "
      "(shore::scenes::sphere_drop_reference_depth, quadrature independent of the column model).");
}

// ---- terrain step alone ---------------------------------------------------------------
void step_alone(const SweepContext& ctx, SweepResult& out) {
  Table& t = out.table("terrain_step_alone", {"case", "threads", "ms_per_substep", "bearing_ms_per_substep",
                                              "active_columns", "erosion_passes", "columns_per_s"});
  const int steps = ctx.quick ? 200 : 600;
  for (const auto c : {scenes::TerrainCase::wheel, scenes::TerrainCase::footprint}) {
    ctx.progress(std::string("terrain step alone, ") + scenes::terrain_case_name(c));
    const scenes::TerrainCaseResult r = scenes::run_terrain_case(c, 1, steps);
    t.add(
        {r.name, 1.0, r.ms_per_step, r.bearing_ms_per_step, r.active_columns, r.erosion_passes, r.columns_per_second});
    if (c == scenes::TerrainCase::wheel) {
      out.figure("terrain.wheel_ms_per_substep", r.ms_per_step, "ms (Terrain::step alone, wheel at 1 cm, 1 thread)");
      out.figure("terrain.wheel_active_columns", r.active_columns, "columns per substep");
    } else {
      out.figure("terrain.footprint_ms_per_substep", r.ms_per_step, "ms (Terrain::step alone, boot at 1 cm, 1 thread)");
    }
  }
  out.note(
      "Terrain step alone (scenes/include/shore/scenes/terrain_step_cases.h): Terrain::step with a prescribed "
      "envelope, no Bullet: a "
      "D 0.8 m, b 0.2 m wheel rolling 3 cm deep at 1 m/s and a boot footprint, 1 cm dry sand, 1/240 s, one thread.");
}

// ---- material map cost ----------------------------------------------------------------
// ms per Terrain::step of the step-alone wheel on `t` (its bearing solved as there).
double wheel_ms(terrain::Terrain& t, int steps) {
  using Clock = std::chrono::steady_clock;
  double seconds = 0.0;
  constexpr int kWarmup = 20;
  for (int k = 0; k < kWarmup + steps; ++k) {
    const EnvelopeRaster env = scenes::wheel_envelope(t, k / 240.0, 0.4 - 0.03, 0.4, 0.2, 0.15);
    const terrain::Imprint im{&env};
    (void)t.bearing_offset(env, 4000.0);
    const auto t0 = Clock::now();
    t.step({&im, 1});
    if (k >= kWarmup) seconds += std::chrono::duration<double>(Clock::now() - t0).count();
  }
  return 1e3 * seconds / steps;
}

// The step-alone wheel on one material against the same wheel on a four-material map whose
// entries are all sand (the same physics, so only the map's cost differs), painted in
// half-metre stripes the wheel crosses. Median of alternating pairs (the machine drifts).
void material_map_cost(const SweepContext& ctx, SweepResult& out) {
  ctx.progress("terrain step alone, four-material map");
  const int steps = ctx.quick ? 200 : 600, pairs = ctx.quick ? 3 : 5;
  std::vector<double> ratios;
  for (int p = 0; p < pairs; ++p) {
    terrain::TerrainSettings s;
    s.cell = 0.01;
    s.threads = 1;
    terrain::Terrain one(s), map(s);
    std::vector<terrain::Material> palette(4, terrain::Material::sand());
    for (int k = 1; k < 4; ++k) palette[static_cast<std::size_t>(k)].name = "sand " + std::to_string(k);
    map.set_palette(palette);
    for (int k = 0; k < 8; ++k) {
      map.paint_rect({k * 50, -20, 50, 20}, k % 4);
      map.paint_rect({k * 50, 0, 50, 20}, (k + 1) % 4);
    }
    const double plain_ms = wheel_ms(one, steps);
    ratios.push_back(wheel_ms(map, steps) / plain_ms);
  }
  std::sort(ratios.begin(), ratios.end());
  out.figure("terrain.material_map_cost_ratio", ratios[ratios.size() / 2],
             "Terrain::step on a four-material map / on one material (step-alone wheel, target <= 1.10)");
}

void run(const SweepContext& ctx, SweepResult& out) {
  step_alone(ctx, out);
  material_map_cost(ctx, out);
  imprint_sweep(ctx, out);
  plate_sweep(ctx, out);
  wheel_sweep(ctx, out);
  sphere_drop_sweep(ctx, out);
}

const SweepRegistrar kRegistered{Sweep{
    .name = "terrain",
    .description = "soil: plate, wheel, imprint and sphere drop against Bekker / exact volumes, vs cell and substep",
    .run = run,
}};

}  // namespace
}  // namespace shore::bench
