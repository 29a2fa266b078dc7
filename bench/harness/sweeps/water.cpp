// water: the spring-mass surface's speed against its error. A square basin of side
// L = 3.2 m, fixed edges, 0.5 m deep (c_w = sqrt(g depth)), undamped. Error: the (2, 3)
// standing mode's frequency against the continuum w = c_w pi sqrt(m^2 + n^2) / L, and the
// drift of the time-centred energy after a local bump (exactly conserved by the continuum).
// Grid spacing is swept at the standard step (1/240 s), the step at the standard spacing
// (5 cm), for the 3-D surface and the vertical-only one.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

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

void run(const SweepContext& ctx, SweepResult& out) {
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
