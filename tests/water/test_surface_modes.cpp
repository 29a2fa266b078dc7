// Lattice modes of a fixed-edge square against the lattice's linear eigenvalue (through
// the scheme's discrete dispersion) and against the continuum wave equation.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "shore/water/surface.h"
#include "water_test_util.h"

using namespace shore::water;
using shore::water::testing::mode_shape;
using shore::water::testing::project;
using shore::water::testing::prony_frequency;
using shore::water::testing::tabulate_mode;

namespace {

/// Linear eigenvalue of a sin-sin mode of the 8-neighbour lattice of vertical stiffness
/// k_t = c (1 - rest_ratio) per spring: w^2 = k_t / m (8 - 2 cos a - 2 cos b - 4 cos a cos b).
double lattice_omega(const LatticeParameters& p, int N, int m, int n) {
  const double a = m * std::numbers::pi / (N - 1), b = n * std::numbers::pi / (N - 1);
  const double kt = p.stiffness * (1.0 - p.rest_ratio);
  return std::sqrt(kt / p.mass * (8.0 - 2.0 * std::cos(a) - 2.0 * std::cos(b) - 4.0 * std::cos(a) * std::cos(b)));
}

/// Semi-implicit Euler's frequency for a mode of frequency w: arccos(1 - w^2 dt^2 / 2) / dt.
double scheme_frequency(double w, double dt) { return std::acos(1.0 - 0.5 * w * w * dt * dt) / dt; }

struct ModeRun {
  double omega = 0.0;     ///< measured, rad/s
  double residual = 0.0;  ///< departure from a pure sinusoid
};

ModeRun run_mode(SurfaceMode mode, const LatticeParameters& p, int N, int m, int n, double amplitude, double dt,
                 double periods) {
  SurfaceSettings s;
  s.nx = s.ny = N;
  s.lattice = p;
  s.lattice.damping = 0.0;
  s.mode = mode;
  s.boundary = Boundary::fixed;
  s.threads = 1;
  Surface surf(s);
  const std::vector<double> phi = tabulate_mode(N, m, n);
  for (int j = 0; j < N; ++j)
    for (int i = 0; i < N; ++i) surf.add_height(i, j, amplitude * mode_shape(N, m, n, i, j));
  const double w = lattice_omega(p, N, m, n);
  const int steps = static_cast<int>(periods * 2.0 * std::numbers::pi / (w * dt));
  std::vector<double> q;
  q.reserve(static_cast<std::size_t>(steps) + 1);
  q.push_back(project(surf, phi));
  for (int k = 0; k < steps; ++k) {
    const StepStats st = surf.step(dt);
    EXPECT_EQ(st.substeps, 1);  // the frequency under test is the one of this dt
    q.push_back(project(surf, phi));
  }
  ModeRun r;
  r.omega = prony_frequency(q, dt, &r.residual);
  return r;
}

struct ModeCase {
  SurfaceMode mode;
  int m, n;
};

std::string case_name(const ::testing::TestParamInfo<ModeCase>& info) {
  const ModeCase& c = info.param;
  return std::string(c.mode == SurfaceMode::full_3d ? "Full3d" : "VerticalOnly") + "_" + std::to_string(c.m) + "_" +
         std::to_string(c.n);
}

class LatticeMode : public ::testing::TestWithParam<ModeCase> {};

TEST_P(LatticeMode, OscillatesAtTheSchemesDiscreteFrequency) {
  const ModeCase mc = GetParam();
  const LatticeParameters p = LatticeParameters::paper();  // h 1, m 4, c 7, rest 0.9
  const int N = 17;
  const double dt = 0.4;  // the paper's step
  // Small amplitude in 3-D so the vertical motion stays linear (tension change ~ 1e-7).
  const double amplitude = mc.mode == SurfaceMode::full_3d ? 1e-3 : 1e-2;
  const ModeRun r = run_mode(mc.mode, p, N, mc.m, mc.n, amplitude, dt, 40.0);
  const double expected = scheme_frequency(lattice_omega(p, N, mc.m, mc.n), dt);
  EXPECT_NEAR(r.omega / expected, 1.0, 1e-5) << "measured " << r.omega << " expected " << expected;
  EXPECT_LT(r.residual, 1e-3);  // it is one clean sinusoid
}

INSTANTIATE_TEST_SUITE_P(Modes, LatticeMode,
                         ::testing::Values(ModeCase{SurfaceMode::vertical_only, 1, 1},
                                           ModeCase{SurfaceMode::vertical_only, 2, 3},
                                           ModeCase{SurfaceMode::full_3d, 1, 1}, ModeCase{SurfaceMode::full_3d, 2, 3}),
                         case_name);

class ContinuumLimit : public ::testing::TestWithParam<ModeCase> {};

TEST_P(ContinuumLimit, ErrorShrinksAtSecondOrder) {
  // Square of side L = 16 m, c_w = 1 m/s fixed while h halves (c scales as 1 / h^2),
  // Courant number c_w dt / h = 0.25. Continuum: w = c_w pi sqrt(m^2 + n^2) / L.
  const ModeCase mc = GetParam();
  const double L = 16.0, cw = 1.0;
  const double continuum = cw * std::numbers::pi * std::sqrt(double(mc.m * mc.m + mc.n * mc.n)) / L;
  double errors[3];
  for (int r = 0; r < 3; ++r) {
    const int cells = 16 << r;
    LatticeParameters p;
    p.spacing = L / cells;
    p.mass = 1.0;
    p.rest_ratio = 0.9;
    p.stiffness = cw * cw * p.mass / (3.0 * p.spacing * p.spacing * (1.0 - p.rest_ratio));
    ASSERT_NEAR(p.wave_speed(), cw, 1e-12);
    const double dt = 0.25 * p.spacing / cw;
    const double amplitude = mc.mode == SurfaceMode::full_3d ? 1e-3 * p.spacing : 1e-2;
    const ModeRun run = run_mode(mc.mode, p, cells + 1, mc.m, mc.n, amplitude, dt, 12.0);
    errors[r] = run.omega / continuum - 1.0;
  }
  EXPECT_LT(std::abs(errors[0]), 0.05);
  for (int r = 0; r < 2; ++r) {
    const double ratio = errors[r] / errors[r + 1];
    EXPECT_GT(ratio, 3.6) << "errors " << errors[r] << " -> " << errors[r + 1];
    EXPECT_LT(ratio, 4.4) << "errors " << errors[r] << " -> " << errors[r + 1];
  }
}

INSTANTIATE_TEST_SUITE_P(Modes, ContinuumLimit,
                         ::testing::Values(ModeCase{SurfaceMode::vertical_only, 1, 1},
                                           ModeCase{SurfaceMode::vertical_only, 2, 3},
                                           ModeCase{SurfaceMode::full_3d, 1, 1}, ModeCase{SurfaceMode::full_3d, 2, 3}),
                         case_name);

}  // namespace
