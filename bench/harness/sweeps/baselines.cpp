// baseline: the yardsticks Shore is compared with, each measured side by side in this run.
// - Plain Bullet on a rigid heightfield: a rigid wheel (D 0.8 m, b 0.3 m, 4 kN: the wheel
//   case of scenes/soil_cases.h) and a box towed at 1 m/s over a flat 1 cm tile, the scene rigid_drop,
//   and the same wheel towed over deformable sand (the cost of deformation). "Error" is the
//   height error of rigid contact: on flat rigid ground the axle should stay at exactly R
//   and the box's underside at exactly 0.
// - Envelope rasterization against one ray cast per column (what a column terrain does
//   without envelopes).
// - The fast water kernel against the plain reference kernel (the paper's algorithm as
//   written), and against the memory floor (a STREAM-style triad in the same run).
// - 1 against 2 threads for the soil step and the water kernel.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "measure.h"
#include "shore/scenes/envelope_cases.h"
#include "shore/scenes/rigid_ground.h"
#include "shore/scenes/runner.h"
#include "shore/scenes/soil_cases.h"
#include "shore/scenes/terrain_step_cases.h"
#include "shore/scenes/water_kernel_cases.h"
#include "shore/scenes/world.h"
#include "shore/water/surface_settings.h"
#include "sweep.h"
#include "sweep_util.h"

namespace shore::bench {
namespace {

constexpr double kCell = 0.01;     // m, tile spacing (the soil's default cell)
constexpr int kColumns = 257;      // 2.56 m tile
constexpr double kTowSpeed = 1.0;  // m/s
constexpr double kTurnX = 0.9;     // m, the tow reverses beyond +-kTurnX (stays on the tile)
constexpr double kWheelRadius = 0.4, kWheelHalfWidth = 0.15, kWheelLoad = 4000.0;  // m, m, N
constexpr double kGravity = 9.81;
const btVector3 kBoxHalf(btScalar(0.15), btScalar(0.15), btScalar(0.1));

enum class Body { wheel, box };

/// A body towed back and forth over flat rigid ground.
class TowedBody {
 public:
  TowedBody(Body kind, double substep) : h_(substep), ground_(world_, settings(), [](double, double) { return 0.0; }) {
    if (kind == Body::wheel) {
      const btVector3 half{btScalar(kWheelRadius), btScalar(kWheelHalfWidth), btScalar(kWheelRadius)};
      body_ = world_.add_body(std::make_unique<btCylinderShape>(half), kWheelLoad / kGravity,
                              btVector3(btScalar(-0.5), 0, btScalar(kWheelRadius)));
      body_->setAngularVelocity(btVector3(0, btScalar(kTowSpeed / kWheelRadius), 0));
      rest_ = kWheelRadius;
    } else {
      body_ = world_.add_body(std::make_unique<btBoxShape>(kBoxHalf), 10.0, btVector3(btScalar(-0.5), 0, kBoxHalf.z()));
      rest_ = kBoxHalf.z();
    }
    body_->setActivationState(DISABLE_DEACTIVATION);
    for (int k = 0; k < static_cast<int>(0.1 / h_); ++k) step();  // settle
    error_sum_ = 0.0;
    error_count_ = 0;
  }

  void step() {
    const double x = body_->getWorldTransform().getOrigin().x();
    if (x > kTurnX) direction_ = -1.0;
    if (x < -kTurnX) direction_ = 1.0;
    btVector3 v = body_->getLinearVelocity();
    v.setX(btScalar(direction_ * kTowSpeed));
    body_->setLinearVelocity(v);
    world_.step(h_);
    error_sum_ += std::abs(static_cast<double>(body_->getWorldTransform().getOrigin().z()) - rest_);
    ++error_count_;
  }
  /// Mean |height error| of the body's centre since construction (after settling), m.
  [[nodiscard]] double mean_error() const { return error_count_ ? error_sum_ / error_count_ : 0.0; }

 private:
  static bullet::HeightfieldTileSettings settings() {
    bullet::HeightfieldTileSettings s;
    s.columns = kColumns;
    s.cell = kCell;
    s.origin_x = s.origin_y = -0.5 * (kColumns - 1) * kCell;
    s.friction = 0.8;
    return s;
  }
  double h_;
  scenes::World world_;
  scenes::RigidGround ground_;
  btRigidBody* body_ = nullptr;
  double rest_ = 0.0;
  double direction_ = 1.0;
  double error_sum_ = 0.0;
  long error_count_ = 0;
};

/// Envelope rasterization against per-column ray casting on the same columns (1 cm).
void envelope_vs_rays(const SweepContext& ctx, SweepResult& out) {
  ctx.progress("envelope vs ray casting, 1 cm, 4 shapes");
  const std::vector<scenes::EnvelopeCaseResult> cases = scenes::run_envelope_cases(0.01, ctx.quick ? 5 : 15);
  Table& t = out.table("baseline_envelope_vs_rays", {"case", "columns", "covered", "envelope_us", "ray_world_us",
                                                     "ray_single_us", "speedup_vs_world_ray", "speedup_vs_single_ray",
                                                     "ray_vs_envelope_mean_abs_mm", "coverage_mismatch"});
  Table& l = out.table("baseline_envelope_methods", {"method", "case", "covered_columns", "us_per_body"});
  double log_sum = 0.0, worst = 1e300, log_single = 0.0;
  for (const scenes::EnvelopeCaseResult& r : cases) {
    t.add({r.name, double(r.columns), double(r.covered), r.envelope_us, r.ray_world_us, r.ray_single_us,
           r.speedup_world, r.speedup_single, r.mean_abs_diff_mm, double(r.coverage_mismatch)});
    l.add({"envelope rasterization", r.name, double(r.covered), r.envelope_us});
    l.add({"ray per column (world rayTest)", r.name, double(r.covered), r.ray_world_us});
    l.add({"ray per column (rayTestSingle)", r.name, double(r.covered), r.ray_single_us});
    log_sum += std::log(r.speedup_world);
    log_single += std::log(r.speedup_single);
    worst = std::min(worst, r.speedup_world);
    if (r.name == "wheel") out.figure("terrain.envelope_vs_raycast_speedup_wheel", r.speedup_world, "x (1 cm)");
  }
  const double n = double(std::max<std::size_t>(cases.size(), 1));
  const double geo = std::exp(log_sum / n);
  out.figure("terrain.envelope_vs_raycast_speedup", geo,
             "x (geometric mean over wheel, sphere, box, hull; one world rayTest per column, 1 cm)");
  out.figure("terrain.envelope_vs_raycast_speedup_min", worst, "x (slowest case)");
  out.figure("terrain.envelope_vs_single_ray_speedup", std::exp(log_single / n),
             "x (geometric mean; rayTestSingle straight at the shape)");
  out.target({.key = "terrain.envelope_vs_raycast_speedup",
              .what = "envelope rasterization vs one ray per column (geometric mean of 4 shapes)",
              .value = geo,
              .op = ">=",
              .threshold = 10.0,
              .unit = "x"});
  out.plot({.name = "baseline_envelope_vs_rays",
            .title = "Lower envelope of one body on a 1 cm grid: rasterization against ray casting",
            .table = "baseline_envelope_methods",
            .x = "covered_columns",
            .y = "us_per_body",
            .series = "method",
            .x_label = "columns the body covers (wheel, box, hull, sphere)",
            .y_label = "microseconds per body and substep"});
  out.note(
      "Envelope vs rays (scenes/include/shore/scenes/envelope_cases.h): the lowest point of a body over every column "
      "of its "
      "window at 1 cm, by Shore's rasterizer or one vertical ray per column (through a btCollisionWorld holding "
      "the body, or rayTestSingle straight at the shape), interleaved, medians. The rasterized envelope is exact "
      "for these shapes; ray_vs_envelope_mean_abs_mm is the single-precision ray test's departure from it.");
}

/// The fast water kernel against the reference kernel, the memory floor, and 1 vs 2 threads.
void water_kernels(const SweepContext& ctx, SweepResult& out) {
  namespace wb = scenes;
  const double min_s = ctx.quick ? 0.2 : 0.6;
  Table& t = out.table("baseline_water_kernels", {"variant", "nodes_per_side", "threads", "ms_per_step",
                                                  "node_steps_per_s", "floor_node_steps_per_s", "fraction_of_floor"});
  ctx.progress("triad bandwidth (float arrays of 128 MB), 1 and 2 threads");
  const double bw[3] = {0.0, wb::triad_bandwidth(std::size_t{1} << 25, 1, min_s),
                        wb::triad_bandwidth(std::size_t{1} << 25, 2, min_s)};
  auto add = [&](const wb::KernelThroughput& r, const std::string& suffix = "") {
    const double floor = wb::floor_node_steps_per_second(r.variant, bw[r.threads]);
    t.add({wb::kernel_variant_name(r.variant) + suffix, double(r.n), double(r.threads), r.seconds_per_step * 1e3,
           r.node_steps_per_second, floor, r.node_steps_per_second / floor});
    return r;
  };
  ctx.progress("water 256^2: fast vs reference kernels, 1 thread");
  const wb::KernelThroughput fast256 = add(wb::measure_kernel_throughput(wb::KernelVariant::fast_3d, 256, 1, min_s));
  const wb::KernelThroughput ref256 =
      add(wb::measure_kernel_throughput(wb::KernelVariant::reference_3d, 256, 1, min_s));
  const wb::KernelThroughput vfast256 =
      add(wb::measure_kernel_throughput(wb::KernelVariant::vertical_only, 256, 1, min_s));
  const wb::KernelThroughput vref256 =
      add(wb::measure_kernel_throughput(wb::KernelVariant::reference_vertical, 256, 1, min_s));
  const double speedup = fast256.node_steps_per_second / ref256.node_steps_per_second;
  out.figure("water.fast_vs_reference_256", speedup, "x (3-D, 256 x 256, 1 thread, same run)");
  out.figure("water.fast_vs_reference_256_vertical", vfast256.node_steps_per_second / vref256.node_steps_per_second,
             "x (vertical-only, 256 x 256, 1 thread)");
  out.target({.key = "water.fast_vs_reference_256",
              .what = "fast 3-D water kernel vs the reference kernel, 256 x 256",
              .value = speedup,
              .op = ">=",
              .threshold = 7.0,
              .unit = "x"});
  out.target({.key = "water.fast_vs_reference_256_vertical",
              .what = "fast vertical-only water kernel vs the reference kernel, 256 x 256",
              .value = vfast256.node_steps_per_second / vref256.node_steps_per_second,
              .op = ">=",
              .threshold = 7.0,
              .unit = "x"});
  // The same cases with other tiles (sleeping is off here, so only the unit of work
  // changes, not the bits): the former default (32) and a larger one, how much of the
  // default case is the fixed cost per tile row (docs/water.md).
  constexpr int kDenseTile = 128;
  const int default_tile = water::SleepSettings{}.tile;
  const std::string dense = "_tile" + std::to_string(kDenseTile);
  for (int tile : {32, kDenseTile}) {
    const std::string suffix = "_tile" + std::to_string(tile);
    ctx.progress("water 256^2: fast kernels with tiles of " + std::to_string(tile));
    const wb::KernelThroughput f =
        add(wb::measure_kernel_throughput(wb::KernelVariant::fast_3d, 256, 1, min_s, tile), suffix);
    const wb::KernelThroughput v =
        add(wb::measure_kernel_throughput(wb::KernelVariant::vertical_only, 256, 1, min_s, tile), suffix);
    out.figure("water.fast_vs_reference_256" + suffix, f.node_steps_per_second / ref256.node_steps_per_second,
               "x (3-D, 256 x 256, 1 thread, tiles of " + std::to_string(tile) + " instead of the default " +
                   std::to_string(default_tile) + "; not the target's case)");
    out.figure("water.fast_vs_reference_256_vertical" + suffix, v.node_steps_per_second / vref256.node_steps_per_second,
               "x (vertical-only, 256 x 256, 1 thread, tiles of " + std::to_string(tile) + ")");
  }

  ctx.progress("water 2048^2: fast kernels against the memory floor, 1 and 2 threads");
  double fraction[3] = {0, 0, 0}, speed[3] = {0, 0, 0};
  for (int threads : {1, 2}) {
    const wb::KernelThroughput r = add(wb::measure_kernel_throughput(wb::KernelVariant::fast_3d, 2048, threads, min_s));
    fraction[threads] = r.node_steps_per_second / wb::floor_node_steps_per_second(r.variant, bw[threads]);
    speed[threads] = r.node_steps_per_second;
    add(wb::measure_kernel_throughput(wb::KernelVariant::vertical_only, 2048, threads, min_s));
  }
  const int headline_threads = std::clamp(ctx.max_threads, 1, 2);
  {
    ctx.progress("water 2048^2: fast 3-D kernel with tiles of " + std::to_string(kDenseTile));
    const wb::KernelThroughput r = add(
        wb::measure_kernel_throughput(wb::KernelVariant::fast_3d, 2048, headline_threads, min_s, kDenseTile), dense);
    out.figure("water.memory_floor_ratio_2048" + dense,
               r.node_steps_per_second / wb::floor_node_steps_per_second(r.variant, bw[headline_threads]),
               "fraction of the triad floor (3-D, 2048 x 2048, " + std::to_string(headline_threads) +
                   " thread(s), tiles of 128; not the target's case)");
  }
  out.figure("water.memory_floor_ratio_2048", fraction[headline_threads],
             "fraction of the triad floor (3-D, 2048 x 2048, " + std::to_string(headline_threads) +
                 " thread(s), 65 B per node-step)");
  out.figure("water.memory_floor_ratio_2048_1t", fraction[1], "fraction (1 thread)");
  out.figure("water.memory_floor_ratio_2048_2t", fraction[2], "fraction (2 threads)");
  out.figure("water.kernel_2048_2t_over_1t", speed[2] / speed[1], "x (fast 3-D, 2048 x 2048, node-steps per second)");
  out.target({.key = "water.kernel_2048_2t_over_1t",
              .what = "two threads never slower than one, fast 3-D kernel at 2048 x 2048",
              .value = speed[2] / speed[1],
              .op = ">=",
              .threshold = 1.0,
              .unit = "x"});
  out.figure("water.triad_gbps_1t_float", bw[1] * 1e-9, "GB/s (float triad, 12 B per element)");
  out.figure("water.triad_gbps_2t_float", bw[2] * 1e-9, "GB/s");
  out.target({.key = "water.memory_floor_ratio_2048",
              .what = "fast 3-D water kernel at 2048 x 2048 as a fraction of the memory floor",
              .value = fraction[headline_threads],
              .op = ">=",
              .threshold = 0.8,
              .unit = "of floor"});
  out.target({.key = "water.memory_floor_ratio_2048_1t",
              .what = "the same with one thread",
              .value = fraction[1],
              .op = ">=",
              .threshold = 0.8,
              .unit = "of floor"});

  ctx.progress("water 1024^2: 1 vs 2 threads");
  const wb::KernelThroughput one = add(wb::measure_kernel_throughput(wb::KernelVariant::fast_3d, 1024, 1, min_s));
  const wb::KernelThroughput two = add(wb::measure_kernel_throughput(wb::KernelVariant::fast_3d, 1024, 2, min_s));
  out.figure("baseline.water_1024_2t_vs_1t_speedup", two.node_steps_per_second / one.node_steps_per_second,
             "x (fast 3-D, 1024 x 1024)");
  out.note(
      "Water kernels (scenes/include/shore/scenes/water_kernel_cases.h): the paper's 8-spring lattice stepped at dt "
      "0.3 with a "
      "disturbance in the middle; fast = Shore's fused SIMD kernel with its stability guard, reference = the plain "
      "loops of the same algorithm (ReferenceSurface). Floor = float triad bandwidth / bytes a node-step must move "
      "(65 B in 3-D and 33 B vertical-only for the fast kernel's fixed-point vertical state, 49 B and 17 B for the "
      "reference), measured with the same thread count in this run. The triad is counted "
      "as STREAM counts it, 12 B per element; its store also reads the line first (write-allocate), so the real "
      "traffic is nearer 16 B and the floor is conservative: fractions can exceed 1 (vertical-only at 2048^2) and "
      "may overstate the kernel's share by up to 4/3. At 256^2 the state fits in the caches and the fraction "
      "means nothing.");
}

/// Threads: the soil step alone (region split even when small) at 1 and 2 threads.
void soil_threads(const SweepContext& ctx, SweepResult& out) {
  namespace tb = scenes;
  Table& t = out.table("baseline_threads_soil", {"case", "threads", "ms_per_substep", "active_columns"});
  const int steps = ctx.quick ? 200 : 600;
  double ms[3] = {0, 0, 0};
  for (int threads : {1, 2}) {
    ctx.progress("soil step alone, wheel at 1 cm, " + std::to_string(threads) + " thread(s), region split forced");
    const tb::TerrainCaseResult r = tb::run_terrain_case(tb::TerrainCase::wheel, threads, steps, true);
    ms[threads] = r.ms_per_step;
    t.add({"wheel, forced split", double(threads), r.ms_per_step, r.active_columns});
  }
  out.figure("baseline.soil_wheel_2t_vs_1t_speedup", ms[1] / ms[2],
             "x (Terrain::step, wheel at 1 cm, region split forced)");
  out.note(
      "Threads: results are bit-identical for any thread count (the tests check it: "
      "SoilRobustness.SameResultWhateverTheThreadCount, SceneSmoke.StateIsBitIdenticalForOneAndTwoThreads); "
      "the speed-up is what a second "
      "core buys on this shared machine. A wheel's active region (about 2,000 columns) normally stays on one "
      "thread (parallel_min_columns 16384): here the split is forced to show its cost.");
}

/// The rigid towed wheel against the same wheel towed over deformable sand.
void deformation_cost(const SweepContext& ctx, SweepResult& out, double rigid_ms) {
  ctx.progress("towed wheel on deformable sand, 1 cm, 1/240 s");
  scenes::WheelCase c;
  c.run.terrain.cell = 0.01;
  c.run.substep = 1.0 / 240;
  c.run.terrain.threads = 1;
  c.towed = true;
  const scenes::WheelResult r = scenes::run_wheel(c);
  Table& t = out.table("baseline_deformation_cost", {"ground", "ms_per_substep", "s_wall_per_s_sim"});
  t.add({"rigid heightfield (Bullet contact)", rigid_ms, rigid_ms * 240e-3});
  t.add({"deformable sand (Shore contact)", r.stats.ms_per_substep(), r.stats.ms_per_substep() * 240e-3});
  out.figure("baseline.deformable_vs_rigid_wheel_cost", r.stats.ms_per_substep() / rigid_ms,
             "x (towed wheel, 1 cm, 1/240 s: Shore sand / rigid Bullet heightfield, whole step)");
  out.note(
      "Cost of deformation: the same wheel (D 0.8 m, b 0.3 m, 4 kN) at 1 cm and 1/240 s, on the rigid heightfield "
      "above (Bullet's cylinder-triangle contact, towed back and forth) and on deformable sand through the plugin "
      "(shore::scenes::run_wheel: load ramp, settling, 2 m towed; Shore owns the soil contact, so Bullet has no "
      "contact to solve). Whole stepSimulation time per substep, one thread.");
}

void run(const SweepContext& ctx, SweepResult& out) {
  const std::vector<double> substeps = ctx.quick
                                           ? std::vector<double>{1.0 / 120, 1.0 / 240, 1.0 / 480}
                                           : std::vector<double>{1.0 / 60, 1.0 / 120, 1.0 / 240, 1.0 / 480, 1.0 / 960};
  const double min_seconds = ctx.quick ? 0.3 : 1.0;
  Table& t = out.table("baseline_rigid_heightfield",
                       {"method", "substep_s", "ms_per_substep", "s_wall_per_s_sim", "height_error_m"});
  double wheel_240 = 0, box_240 = 0;
  for (Body kind : {Body::wheel, Body::box}) {
    const std::string method = kind == Body::wheel ? "rigid_heightfield_wheel" : "rigid_heightfield_box";
    for (double h : substeps) {
      ctx.progress(method + ", substep " + substep_label(h));
      TowedBody body(kind, h);
      const int batch = std::max(1, static_cast<int>(std::lround(0.05 / h)));  // 50 ms simulated per call
      const Measurement m = measure(
          [&] {
            for (int k = 0; k < batch; ++k) body.step();
          },
          min_seconds, 5);
      const double ms = m.median_s / batch * 1e3;
      t.add({method, h, ms, ms * 1e-3 / h, body.mean_error()});
      if (std::abs(h - 1.0 / 240) < 1e-12) (kind == Body::wheel ? wheel_240 : box_240) = ms;
    }
  }
  // The scene, reused: a box dropped onto a rippled rigid tile (simulation loop only).
  if (const scenes::SceneType* scene = scenes::find_scene("rigid_drop")) {
    for (double h : substeps) {
      ctx.progress("rigid_drop scene, substep " + substep_label(h));
      scenes::Overrides o;
      o.smoke = true;
      o.threads = 1;
      o.write_files = false;
      o.substep = h;
      const scenes::SceneResult r = scenes::run_scene(*scene, scenes::resolve(*scene, o), scenes::ProgressMode::quiet);
      const double ms = r.metrics["wall_seconds"].get<double>() / r.metrics["substeps"].get<double>() * 1e3;
      t.add({"rigid_drop_scene", h, ms, ms * 1e-3 / h, std::abs(r.metrics["rest_gap_m"].get<double>())});
    }
  }
  out.figure("baseline.rigid_heightfield_wheel_ms_per_substep", wheel_240, "ms (substep 1/240 s, 1 cm tile)");
  out.figure("baseline.rigid_heightfield_wheel_s_per_sim_s", wheel_240 * 1e-3 * 240,
             "s wall per s simulated (1/240 s)");
  out.figure("baseline.rigid_heightfield_box_ms_per_substep", box_240, "ms (substep 1/240 s, 1 cm tile)");
  out.plot({.name = "baseline_time_vs_error",
            .title = "Plain Bullet on a rigid 1 cm heightfield: cost against height error",
            .table = "baseline_rigid_heightfield",
            .x = "height_error_m",
            .y = "s_wall_per_s_sim",
            .series = "method",
            .x_label = "mean height error of rigid contact, m",
            .y_label = "wall seconds per simulated second"});
  out.plot({.name = "baseline_cost_vs_substep",
            .title = "Plain Bullet on a rigid 1 cm heightfield: cost per substep",
            .table = "baseline_rigid_heightfield",
            .x = "substep_s",
            .y = "ms_per_substep",
            .series = "method",
            .x_label = "substep, s",
            .y_label = "ms per substep"});
  out.note(
      "Rigid wheel: cylinder D 0.8 m, b 0.3 m, 4 kN (407.7 kg), towed back and forth at 1 m/s over a flat "
      "257 x 257 tile at 1 cm; box: 0.3 x 0.3 x 0.2 m, 10 kg, towed the same way; rigid_drop_scene: the demo "
      "scene's smoke run (simulation loop only, error = |rest gap|). One thread, Bullet's own collision and "
      "solver; height_error_m is the mean |centre height - rest height| while towed.");
  deformation_cost(ctx, out, wheel_240);
  envelope_vs_rays(ctx, out);
  water_kernels(ctx, out);
  soil_threads(ctx, out);
}

const SweepRegistrar kRegistered{Sweep{
    .name = "baseline",
    .description = "yardsticks: rigid Bullet heightfield, envelope vs ray casting, water kernels vs reference and "
                   "memory floor, 1 vs 2 threads",
    .run = run,
}};

}  // namespace
}  // namespace shore::bench
