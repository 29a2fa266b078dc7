// water: the spring-mass surface's speed against its error. A square basin of side
// L = 3.2 m, fixed edges, 0.5 m deep (c_w = sqrt(g depth)), undamped. Error: the (2, 3)
// standing mode's frequency against the continuum w = c_w pi sqrt(m^2 + n^2) / L, and the
// drift of the time-centred energy after a local bump (exactly conserved by the continuum).
// Grid spacing is swept at the standard step (1/240 s), the step at the standard spacing
// (5 cm), for the 3-D surface and the vertical-only one.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include "loaded_pair.h"
#include "shore/scenes/water_cases.h"
#include "shore/scenes/water_kernel_cases.h"
#include "shore/water/surface.h"
#include "sweep.h"
#include "sweep_util.h"

namespace shore::bench {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kSide = 3.2, kDepth = 0.5, kGravity = 9.81;  // m, m, m/s^2
constexpr int kModeM = 2, kModeN = 3;
constexpr double kStandardCell = 0.05, kStandardStep = 1.0 / 240;
constexpr double kSimSeconds = 8.0;  // s: ten periods of the (2, 3) mode

double continuum_omega() {
  const double cw = std::sqrt(kGravity * kDepth);
  return cw * std::numbers::pi * std::sqrt(double(kModeM * kModeM + kModeN * kModeN)) / kSide;
}

water::Surface make_surface(water::SurfaceMode mode, double cell) {
  water::PhysicalParameters p;
  p.cell = cell;
  p.depth = kDepth;
  p.damping_time = std::numeric_limits<double>::infinity();
  const int nodes = static_cast<int>(std::lround(kSide / cell)) + 1;
  water::SurfaceSettings s = water::SurfaceSettings::physical(p, nodes, nodes);
  s.mode = mode;
  s.boundary = water::Boundary::fixed;
  s.threads = 1;
  return water::Surface(s);
}

double mode_shape(int nodes, int i, int j) {
  const double L = nodes - 1;
  return std::sin(kModeM * std::numbers::pi * i / L) * std::sin(kModeN * std::numbers::pi * j / L);
}

/// Least-squares amplitude of the mode in the heights.
double project(const water::Surface& s, const std::vector<double>& phi) {
  const std::vector<double> uz = s.dense_state().uz;
  double num = 0.0, den = 0.0;
  for (std::size_t k = 0; k < phi.size(); ++k) {
    num += phi[k] * uz[k];
    den += phi[k] * phi[k];
  }
  return num / den;
}

/// Frequency of a sampled sinusoid (Prony): q[k+1] + q[k-1] = 2 cos(w dt) q[k], least squares.
double prony_omega(const std::vector<double>& q, double dt) {
  double num = 0.0, den = 0.0;
  for (std::size_t k = 1; k + 1 < q.size(); ++k) {
    num += q[k] * (q[k + 1] + q[k - 1]);
    den += 2.0 * q[k] * q[k];
  }
  return std::acos(std::clamp(num / den, -1.0, 1.0)) / dt;
}

struct ModeRun {
  double omega = 0.0;           ///< rad/s, measured
  double seconds_stepping = 0;  ///< wall time inside step()
  long substeps = 0;            ///< internal substeps taken
  double substep = 0.0;         ///< s, their length
};

ModeRun run_mode(water::SurfaceMode mode, double cell, double dt) {
  water::Surface s = make_surface(mode, cell);
  const int nodes = s.nx();
  std::vector<double> phi(s.node_count());
  const double amplitude = mode == water::SurfaceMode::full_3d ? 1e-3 * cell : 1e-2;  // m, linear regime
  for (int j = 0; j < nodes; ++j)
    for (int i = 0; i < nodes; ++i) {
      phi[std::size_t(j) * nodes + i] = mode_shape(nodes, i, j);
      s.add_height(i, j, amplitude * phi[std::size_t(j) * nodes + i]);
    }
  const long steps = std::lround(kSimSeconds / dt);
  std::vector<double> q;
  q.reserve(std::size_t(steps) + 1);
  q.push_back(project(s, phi));
  ModeRun r;
  for (long k = 0; k < steps; ++k) {
    const auto t0 = Clock::now();
    const water::StepStats st = s.step(dt);
    r.seconds_stepping += std::chrono::duration<double>(Clock::now() - t0).count();
    r.substeps += st.substeps;
    r.substep = st.substep;
    q.push_back(project(s, phi));
  }
  r.omega = prony_omega(q, dt);
  return r;
}

struct EnergyRun {
  double drift_pct = 0.0;    ///< 100 (E_end - E_0) / E_0, time-centred energy
  double max_dev_pct = 0.0;  ///< 100 max |E(t) - E_0| / E_0
};

/// A Gaussian bump (sigma 3 cells, 1 cm high in vertical-only, 0.1 cell in 3-D) off centre,
/// run as long as the mode; energy sampled every few steps.
EnergyRun run_energy(water::SurfaceMode mode, double cell, double dt) {
  water::Surface s = make_surface(mode, cell);
  const double amplitude = mode == water::SurfaceMode::full_3d ? 0.1 * cell : 0.01;
  s.disturb(
      water::Disturbance::point_height(s.node_x(0) + 0.37 * kSide, s.node_y(0) + 0.41 * kSide, 3.0 * cell, amplitude));
  const double e0 = s.energy().centred;
  const long steps = std::lround(kSimSeconds / dt);
  const long every = std::max(1L, steps / 400);
  EnergyRun r;
  double e = e0;
  for (long k = 1; k <= steps; ++k) {
    s.step(dt);
    if (k % every == 0 || k == steps) {
      e = s.energy().centred;
      r.max_dev_pct = std::max(r.max_dev_pct, 100.0 * std::abs(e - e0) / e0);
    }
  }
  r.drift_pct = 100.0 * (e - e0) / e0;
  return r;
}

const char* mode_name(water::SurfaceMode m) { return m == water::SurfaceMode::full_3d ? "3-D" : "vertical-only"; }

/// Volume of a closed pool and energy of the undamped 3-D lattice over 100,000 steps.
void conservation(const SweepContext& ctx, SweepResult& out) {
  Table& t = out.table("water_conservation", {"quantity", "mode", "nodes", "steps", "value", "exact", "seconds"});
  double worst = 0.0;
  for (const auto mode : {water::SurfaceMode::vertical_only, water::SurfaceMode::full_3d}) {
    scenes::DriftCase c;
    c.mode = mode;
    c.nodes = ctx.quick && mode == water::SurfaceMode::full_3d ? 33 : 65;
    ctx.progress(std::string("closed pool, ") + mode_name(mode) + ", 100000 steps");
    const scenes::DriftResult r = scenes::run_closed_pool(c);
    t.add({"volume drift / bump volume", mode_name(mode), double(c.nodes), double(c.steps), r.volume_drift,
           r.exact ? "yes" : "no", r.seconds});
    worst = std::max(worst, r.volume_drift);
  }
  out.figure("water.volume_drift_100k", worst, "of the bump's volume, worst of both modes (closed pool, 1e5 steps)");
  out.target({.key = "water.volume_drift_100k",
              .what = "closed pool's volume over 100,000 steps",
              .value = worst,
              .op = "<=",
              .threshold = 1e-9,
              .unit = "relative"});
  scenes::EnergyCase e;
  e.steps = ctx.quick ? 20000 : 100000;
  ctx.progress("undamped 3-D lattice at 0.003 h, " + std::to_string(e.steps) + " steps");
  const auto t0 = Clock::now();
  const double gain = scenes::energy_gain(e);
  t.add({"time-centred energy gain", "3-D", 65.0, double(e.steps), gain, "-",
         std::chrono::duration<double>(Clock::now() - t0).count()});
  out.figure("water.energy_gain_small_amplitude", gain,
             "relative, undamped 3-D at 0.003 h over " + std::to_string(e.steps) + " steps");
  out.target({.key = "water.energy_gain_small_amplitude",
              .what = "energy gain of small waves, undamped 3-D lattice",
              .value = gain,
              .op = "<=",
              .threshold = 1e-4,
              .unit = "relative"});
  out.note(
      "Conservation: a closed pool (65 x 65 at 5 cm, 0.5 m deep, vertical-only walls, damping time 2 s; 33 x 33 for "
      "3-D in quick runs) with a 1 cm Gaussian bump (sigma 3 cells), 100,000 steps of 1/240 s, sleeping tiles on: the "
      "largest |V(t) - V(0)| over the bump's volume (exact: the same bits at every check). Heights and vertical "
      "velocities are fixed-point doubles, spring impulses equal and opposite, the rounding of damping and rise "
      "put back exactly on one node (docs/water.md). Energy: the undamped 3-D lattice (65 x 65, fixed edges) with "
      "a bump of 0.003 h, the largest rise of the time-centred energy over its start.");
}

/// A ring's echo from an open edge against the layer's width, and from walls.
void reflection(const SweepContext& ctx, SweepResult& out) {
  Table& t = out.table("water_open_edge", {"edge", "width_nodes", "strength", "echo_over_amplitude"});
  for (const auto b : {water::Boundary::fixed, water::Boundary::vertical_only}) {
    const scenes::EchoResult r = scenes::measure_echo({.boundary = b});
    t.add({b == water::Boundary::fixed ? "fixed" : "vertical-only", 0.0, 0.0, r.ratio()});
  }
  double at_default = 0.0;
  const std::vector<int> widths = ctx.quick ? std::vector<int>{8, 16, 32} : std::vector<int>{8, 12, 16, 24, 32, 48};
  for (int w : widths) {
    ctx.progress("ring's echo from an open edge, layer of " + std::to_string(w) + " nodes");
    const scenes::EchoResult r = scenes::measure_echo({.width = w});
    t.add({"open", double(w), 6.0, r.ratio()});
    if (w == water::OpenBoundarySettings{}.width) at_default = r.ratio();
  }
  out.figure("water.open_edge_reflection", at_default, "of the ring's amplitude (open edge, default layer)");
  out.target({.key = "water.open_edge_reflection",
              .what = "a ring's echo from an open edge",
              .value = at_default,
              .op = "<=",
              .threshold = 0.05,
              .unit = "of its amplitude"});
  out.plot({.name = "water_open_edge_reflection",
            .title = "Echo of a ring from an open edge against the absorbing layer's width",
            .table = "water_open_edge",
            .x = "width_nodes",
            .y = "echo_over_amplitude",
            .series = "edge",
            .x_label = "layer width, nodes",
            .y_label = "echo / ring amplitude"});
  out.note(
      "Open edge: a 1 mm ring (sigma 2 cells, 5 cm, 0.5 m deep, undamped, vertical-only) 30 nodes from the edge of "
      "the water; echo = the largest difference at the source from a run whose edges are too far to echo, over "
      "the ring's amplitude at twice the distance (a perfect mirror's echo). Fixed and vertical-only edges are "
      "listed at width 0.");
}

/// Water steps with 1 and 2 threads, interleaved, on a machine loaded by busy threads.
void threads(const SweepContext& ctx, SweepResult& out) {
  Table& t = out.table("water_threads", {"mode", "nodes_per_side", "load_threads", "ms_per_step_1t", "ms_per_step_2t",
                                         "speed_2t_over_1t"});
  const std::vector<int> sizes =
      ctx.quick ? std::vector<int>{64, 256, 1024} : std::vector<int>{64, 128, 256, 512, 1024, 2048};
  const int load = busy_load_threads();
  double worst = 1e300;
  const char* policy = std::getenv("OMP_WAIT_POLICY");
  for (const auto mode : {water::SurfaceMode::vertical_only, water::SurfaceMode::full_3d}) {
    for (int n : sizes) {
      ctx.progress(std::string(mode_name(mode)) + " water " + std::to_string(n) + "^2: 1 vs 2 threads under load");
      water::Surface one(scenes::kernel_case_settings(
          mode == water::SurfaceMode::full_3d ? scenes::KernelVariant::fast_3d : scenes::KernelVariant::vertical_only,
          n, 1));
      water::SurfaceSettings s2 = one.settings();
      s2.threads = 2;
      water::Surface two(s2);
      for (water::Surface* s : {&one, &two})
        s->disturb(water::Disturbance::point_height(0.5 * (n - 1), 0.5 * (n - 1), 3.0, 1.0));
      const BusyLoad busy(load);
      const PairTiming p = time_alternating([&] { one.step(0.3); }, [&] { two.step(0.3); }, ctx.quick ? 0.03 : 0.08,
                                            ctx.quick ? 15 : 25);
      const double m1 = p.s_per_step_1, m2 = p.s_per_step_2, r = p.speed_2_over_1;
      t.add({mode_name(mode), double(n), double(load), 1e3 * m1, 1e3 * m2, r});
      worst = std::min(worst, r);
    }
  }
  out.figure("water.threads2_vs_1_min_speedup", worst,
             std::string("x, worst grid size, 2 threads over 1 on a machine loaded by busy threads (OMP_WAIT_POLICY ") +
                 (policy ? std::string("= ") + policy : std::string("unset")) + ")");
  out.target({.key = "water.threads2_vs_1_min_speedup",
              .what = "2 threads at least 0.9 x the speed of 1 at every grid size, loaded machine",
              .value = worst,
              .op = ">=",
              .threshold = 0.9,
              .unit = "x"});
  out.note(std::string("Threads: the paper's lattice (vertical-only and 3-D, dense grid, a bump in the middle) at dt "
                       "0.3, steps timed in short slices alternating 1 and 2 threads while busy threads load every "
                       "core; speed = the median of the ratio of adjacent slices. The surface's team takes no OpenMP "
                       "(OMP_WAIT_POLICY changes nothing in it; ") +
           (policy ? std::string("it was ") + policy : std::string("it was unset")) +
           " in this run); a step forks only above parallel_min_nodes and while parallel substeps measure faster.");
}

/// Microseconds per substep of a 1 km lake (the lake case's settings, one thread) whose
/// tiles all sleep: never touched (no tile created) or woken in 16 places and left to
/// settle (tiles created, all asleep again).
struct AsleepLake {
  double untouched_us = 0.0, settled_us = 0.0;
  std::int64_t settled_tiles = 0;  ///< tiles created (asleep) in the settled lake
};
AsleepLake asleep_lake(const scenes::LakeCase& c, bool quick) {
  scenes::LakeCase one_thread = c;
  one_thread.threads = 1;
  const water::SurfaceSettings s = scenes::lake_surface(one_thread);
  const int steps = quick ? 2000 : 20000;
  const auto per_substep_us = [&](water::Surface& lake) {
    const auto t0 = Clock::now();
    int substeps = 0;
    for (int k = 0; k < steps; ++k) substeps += lake.step(c.substep).substeps;
    return 1e6 * std::chrono::duration<double>(Clock::now() - t0).count() / std::max(substeps, 1);
  };
  AsleepLake r;
  water::Surface untouched(s);
  r.untouched_us = per_substep_us(untouched);
  water::Surface settled(s);
  for (int k = 0; k < 16; ++k) {
    const double x = (0.1 + 0.05 * k) * c.side, y = (0.9 - 0.05 * k) * c.side;
    settled.wake(x, y, x + 10.0, y + 10.0);
  }
  for (int k = 0; k < 10000 && settled.tile_stats().awake > 0; ++k) settled.step(c.substep);
  r.settled_tiles = settled.tile_stats().created;
  if (settled.tile_stats().awake == 0) r.settled_us = per_substep_us(settled);
  return r;
}

/// A 1 km lake at 10 cm with a boat crossing it: creation, memory, cost against the wake.
void lake(const SweepContext& ctx, SweepResult& out) {
  scenes::LakeCase c;
  c.seconds = ctx.quick ? 8.0 : 20.0;
  ctx.progress("1 km x 1 km lake at 10 cm, a boat at 2 m/s for " + std::to_string(int(c.seconds)) + " s");
  const scenes::LakeResult r = scenes::run_lake(c);
  Table& t = out.table("water_lake",
                       {"t_s", "awake_nodes", "woken_nodes", "memory_mb", "ms_per_substep", "ns_per_awake_node"});
  double worst_memory = 0.0;
  std::vector<double> per_node;
  for (const scenes::LakeSample& s : r.samples) {
    // Over the nodes awake while the time was taken, not those at the sample's end: in a
    // growing wake those are 10 to 20 % more, and the figure would read that much low.
    const double ns = s.mean_awake_nodes > 0 ? 1e6 * s.step_ms / s.mean_awake_nodes : 0.0;
    t.add({s.t, double(s.awake_nodes), double(s.woken_nodes), 1e-6 * double(s.memory_bytes), s.step_ms, ns});
    if (s.woken_nodes > 0)
      worst_memory = std::max(worst_memory, double(s.memory_bytes) / (17.0 * double(s.woken_nodes)));
    if (s.mean_awake_nodes > 0) per_node.push_back(ns);
  }
  std::sort(per_node.begin(), per_node.end());
  out.figure("water.lake_creation_ms", r.creation_ms, "ms to create 1e8 virtual nodes");
  out.figure("water.lake_empty_memory_mb", 1e-6 * double(r.empty_memory_bytes), "MB right after creation");
  out.figure("water.lake_memory_over_woken_area", worst_memory,
             "x a dense grid's state (17 B per node) of the tiles ever woken, worst sample");
  const double ns_per_node = per_node.empty() ? 0.0 : per_node[per_node.size() / 2];
  out.figure("water.lake_ns_per_awake_node", ns_per_node,
             "ns per awake node and substep (water + coupling), median sample");
  out.target({.key = "water.lake_ns_per_awake_node",
              .what = "lake cost per awake node, half of the 3.3 ns of 2026-12-04",
              .value = ns_per_node,
              .op = "<=",
              .threshold = 1.65,
              .unit = "ns"});
  ctx.progress("1 km lake asleep: untouched, and settled after waking 16 places");
  const AsleepLake quiet = asleep_lake(c, ctx.quick);
  out.figure("water.lake_asleep_us_per_substep", std::max(quiet.untouched_us, quiet.settled_us),
             "us per substep, 1 km lake with every tile asleep, the worse of untouched and settled (" +
                 std::to_string(quiet.settled_tiles) + " tiles created, asleep)");
  out.figure("water.lake_untouched_us_per_substep", quiet.untouched_us, "us per substep, no tile ever created");
  out.figure("water.lake_settled_us_per_substep", quiet.settled_us,
             "us per substep, tiles created and all asleep again (0: they did not settle)");
  out.target({.key = "water.lake_asleep_us_per_substep",
              .what = "a fully asleep 1 km lake per substep",
              .value = std::max(quiet.untouched_us, quiet.settled_us),
              .op = "<=",
              .threshold = 1.0,
              .unit = "us"});
  out.target({.key = "water.lake_memory_over_woken_area",
              .what = "lake memory against the woken area",
              .value = worst_memory,
              .op = "<=",
              .threshold = 5.0,
              .unit = "x"});
  out.plot({.name = "water_lake_cost_vs_awake",
            .title = "1 km lake at 10 cm, a boat at 2 m/s: cost per substep against awake nodes",
            .table = "water_lake",
            .x = "awake_nodes",
            .y = "ms_per_substep",
            .series = "",
            .x_label = "awake nodes",
            .y_label = "ms per substep (water + coupling)"});
  out.note(
      "Lake: 1 km x 1 km at 10 cm (10001^2 = 1e8 nodes, vertical-only, 2 m deep, open edges), a kinematic boat (a 2 x "
      "1 m box at 0.3 m draft) crossing it at 2 m/s from the middle, 1/60 s substeps, one thread; once a second "
      "the awake nodes, the nodes of tiles ever woken, the surface's memory and the mean cost of a substep.");
}

void run(const SweepContext& ctx, SweepResult& out) {
  conservation(ctx, out);
  reflection(ctx, out);
  threads(ctx, out);
  lake(ctx, out);
  Table& t = out.table("water_modes",
                       {"curve", "method", "varied", "cell_m", "nodes", "dt_s", "substep_s", "ms_per_substep",
                        "s_wall_per_s_sim", "omega_rad_s", "continuum_rad_s", "freq_error_pct", "abs_freq_error_pct",
                        "energy_drift_pct", "abs_energy_drift_pct", "energy_max_dev_pct"});
  const std::vector<double> cells =
      ctx.quick ? std::vector<double>{0.1, 0.05, 0.025} : std::vector<double>{0.2, 0.1, 0.05, 0.025, 0.0125};
  const std::vector<double> steps = ctx.quick
                                        ? std::vector<double>{1.0 / 60, 1.0 / 240, 1.0 / 960}
                                        : std::vector<double>{1.0 / 60, 1.0 / 120, 1.0 / 240, 1.0 / 480, 1.0 / 960};
  const double w_ref = continuum_omega();
  for (const auto mode : {water::SurfaceMode::full_3d, water::SurfaceMode::vertical_only}) {
    const std::string method = mode_name(mode);
    for (const CrossPoint& p : cross(cells, steps, kStandardCell, kStandardStep)) {
      ctx.progress(method + ", " + cell_label(p.cell) + ", dt " + substep_label(p.substep));
      const ModeRun m = run_mode(mode, p.cell, p.substep);
      const EnergyRun e = run_energy(mode, p.cell, p.substep);
      const double err = error_pct(m.omega, w_ref);
      const double ms = m.substeps ? 1e3 * m.seconds_stepping / double(m.substeps) : NAN;
      const double nodes = std::lround(kSide / p.cell) + 1;
      auto row = [&](const std::string& curve, const char* varied) {
        return std::vector<Cell>{curve,         method,      varied,
                                 p.cell,        nodes,       p.substep,
                                 m.substep,     ms,          m.seconds_stepping / kSimSeconds,
                                 m.omega,       w_ref,       err,
                                 std::abs(err), e.drift_pct, std::abs(e.drift_pct),
                                 e.max_dev_pct};
      };
      if (p.on_cell_axis) t.add(row(method + " vs spacing", "cell"));
      if (p.on_substep_axis) t.add(row(method + " vs dt", "dt"));
      if (same(p.cell, kStandardCell) && same(p.substep, kStandardStep)) {
        const std::string key = mode == water::SurfaceMode::full_3d ? "3d" : "vertical";
        out.figure("water.mode_error_pct_" + key, err, "% vs continuum (5 cm, 1/240 s)");
        out.figure("water.energy_drift_pct_" + key, e.drift_pct, "% over 8 s (5 cm, 1/240 s, undamped)");
        out.figure("water.ms_per_substep_" + key + "_65x65", ms, "ms (65 x 65 nodes, 1 thread)");
      }
    }
  }
  ctx.progress("paper grid");
  const double paper_ms = 1e3 * scenes::paper_grid_seconds_per_step(1, ctx.quick ? 0.3 : 1.0);
  out.figure("water.paper_grid_ms_per_step", paper_ms, "ms (50 x 50, dt 0.4, 3-D, 1 thread; paper: 4.8 ms)");

  out.plot({.name = "water_modes_time_vs_error",
            .title = "Water (2,3) mode in a 3.2 m basin: cost against frequency error (continuum)",
            .table = "water_modes",
            .x = "abs_freq_error_pct",
            .y = "s_wall_per_s_sim",
            .series = "curve",
            .x_label = "|frequency error|, % of c_w pi sqrt(13) / L",
            .y_label = "wall seconds per simulated second"});
  out.plot({.name = "water_energy_time_vs_drift",
            .title = "Water, undamped bump: cost against energy drift over 8 s",
            .table = "water_modes",
            .x = "abs_energy_drift_pct",
            .y = "s_wall_per_s_sim",
            .series = "curve",
            .x_label = "|time-centred energy drift|, % of the initial energy",
            .y_label = "wall seconds per simulated second"});
  char note[900];
  std::snprintf(note, sizeof note,
                "Water: square basin L = %.1f m, fixed edges, depth %.1f m (c_w = %.3f m/s), undamped, one thread. "
                "Frequency: the (2, 3) mode (linear amplitude) projected on its shape every step and fitted with "
                "Prony over %.0f s, against the continuum %.3f rad/s; it includes the lattice's dispersion and the "
                "time scheme's. Energy: a Gaussian bump (sigma 3 cells) run %.0f s, drift of the time-centred "
                "energy. dt is the step asked for; the stability guard splits it (substep_s) where needed, so "
                "the 3-D surface's error stops changing once dt exceeds its stable step. Cost: wall time inside "
                "step() only.",
                kSide, kDepth, std::sqrt(kGravity * kDepth), kSimSeconds, w_ref, kSimSeconds);
  out.note(note);
}

const SweepRegistrar kRegistered{Sweep{
    .name = "water",
    .description = "water surface: mode frequency vs continuum and energy drift, vs spacing and dt, 3-D and vertical",
    .run = run,
}};

}  // namespace
}  // namespace shore::bench
