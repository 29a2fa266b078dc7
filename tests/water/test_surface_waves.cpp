// Rings and reflections: symmetry of a ring from a central disturbance, and the sign of a
// wave reflected by a fixed edge (Dirichlet: inverted) and by a vertical-only wall
// (Neumann: not inverted), against the image construction for the wave equation.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "shore/water/surface.h"

using namespace shore::water;

namespace {

std::string mode_name(const ::testing::TestParamInfo<SurfaceMode>& info) {
  return info.param == SurfaceMode::full_3d ? "Full3d" : "VerticalOnly";
}

class WaterRing : public ::testing::TestWithParam<SurfaceMode> {};

TEST_P(WaterRing, IsSymmetricUnderTheGridsEightSymmetries) {
  const int N = 41;
  SurfaceSettings s;
  s.nx = s.ny = N;
  s.lattice = LatticeParameters::paper();
  s.mode = GetParam();
  s.threads = 1;
  s.origin_x = 100.0;  // away from the origin: the state is stored relative to rest
  s.origin_y = -50.0;
  Surface surf(s);
  // 0.3 h: steep enough for a clear ring, gentle enough that no spring is compressed (a
  // compressed pre-tensioned lattice buckles in-plane, which amplifies rounding noise).
  surf.disturb(Disturbance::point_height(surf.node_x(20), surf.node_y(20), 2.0, 0.3));
  for (int k = 0; k < 120; ++k) surf.step(0.4);  // the ring reaches the edges and comes back
  const DenseState v = surf.dense_state();
  const auto at = [N](const auto& a, int i, int j) {
    return static_cast<double>(a[static_cast<std::size_t>(j * N + i)]);
  };
  double scale = 0.0, worst = 0.0, worst_plane = 0.0;
  for (double x : v.uz) scale = std::max(scale, static_cast<double>(std::abs(x)));
  ASSERT_GT(scale, 1e-3);
  const bool full = GetParam() == SurfaceMode::full_3d;
  for (int j = 0; j < N; ++j) {
    for (int i = 0; i < N; ++i) {
      const double z = at(v.uz, i, j);
      // Transpose and the two mirrors generate the whole dihedral group of the square.
      worst = std::max({worst, std::abs(z - at(v.uz, j, i)), std::abs(z - at(v.uz, N - 1 - i, j)),
                        std::abs(z - at(v.uz, i, N - 1 - j))});
      if (full) {
        const double x = at(v.ux, i, j);
        worst_plane = std::max({worst_plane, std::abs(x + at(v.ux, N - 1 - i, j)), std::abs(x - at(v.ux, i, N - 1 - j)),
                                std::abs(x - at(v.uy, j, i))});
      }
    }
  }
  EXPECT_LT(worst, 1e-5 * scale);
  // In-plane forces are small differences of pre-tension forces c (h - L0) that a mirror
  // image sums in another order: their rounding scale is float epsilon times the lattice.
  EXPECT_LT(worst_plane, 1e-5 * s.lattice.spacing);
}

INSTANTIATE_TEST_SUITE_P(Modes, WaterRing, ::testing::Values(SurfaceMode::vertical_only, SurfaceMode::full_3d),
                         mode_name);

struct ReflectionCase {
  SurfaceMode mode;
  NodeConstraint wall;
};

class WaterReflection : public ::testing::TestWithParam<ReflectionCase> {};

TEST_P(WaterReflection, MatchesTheImageSource) {
  // A ring starts at S, 30 nodes from the left edge. By the image construction the wave that
  // comes back to S from a straight wall is the direct wave at distance 2d, times -1 for a
  // Dirichlet wall (fixed nodes, wall on the node line, d = 30 h) and +1 for a Neumann wall
  // (vertical-only nodes with springs on one side: mirror half a cell out, d = 30.5 h). The
  // direct wave at distance 2d is probed at P = S + 2d along x, on the far side, in the same
  // run. Both paths run along the x axis, so lattice dispersion is the same for both.
  const ReflectionCase rc = GetParam();
  const bool dirichlet = rc.wall == NodeConstraint::fixed;
  SurfaceSettings s;
  s.nx = 200;
  s.ny = 141;
  s.lattice = LatticeParameters::paper();
  s.lattice.damping = 0.0;
  s.mode = rc.mode;
  s.boundary = Boundary::fixed;
  s.threads = 1;
  Surface surf(s);
  for (int j = 1; j < s.ny - 1; ++j) surf.set_constraint(0, j, rc.wall);
  const int si = 30, sj = 70;
  const double d = dirichlet ? 30.0 : 30.5;
  const int pi = si + static_cast<int>(2.0 * d);
  const double sigma = 2.0;
  const double amplitude = rc.mode == SurfaceMode::full_3d ? 0.01 : 1.0;
  surf.disturb(Disturbance::point_height(surf.node_x(si), surf.node_y(sj), sigma, amplitude));
  const double cw = s.lattice.wave_speed(), dt = 0.4;
  std::vector<double> at_source, at_probe;
  for (int k = 1; k * dt * cw < 2.0 * d + 5.0 * sigma; ++k) {
    surf.step(dt);
    if (k * dt * cw < 2.0 * d - 5.0 * sigma) continue;  // before the reflection arrives
    at_source.push_back(surf.height(si, sj));
    at_probe.push_back(surf.height(pi, sj));
  }
  const double sign = dirichlet ? -1.0 : 1.0;
  double peak = 0.0, diff = 0.0, s11 = 0.0, s22 = 0.0, s12 = 0.0;
  for (std::size_t k = 0; k < at_probe.size(); ++k) {
    peak = std::max(peak, std::abs(at_probe[k]));
    diff = std::max(diff, std::abs(at_source[k] - sign * at_probe[k]));
    s11 += at_source[k] * at_source[k];
    s22 += at_probe[k] * at_probe[k];
    s12 += at_source[k] * at_probe[k];
  }
  ASSERT_GT(peak, 0.02 * amplitude);  // the direct wave did pass the probe in the window
  const double correlation = s12 / std::sqrt(s11 * s22);
  EXPECT_GT(sign * correlation, 0.98) << "correlation of the reflected with the direct wave " << correlation;
  RecordProperty("difference_over_peak", std::to_string(diff / peak));
  RecordProperty("correlation", std::to_string(correlation));
  EXPECT_LT(diff, 0.05 * peak) << "reflection differs from the image wave by " << diff << " of " << peak;
}

INSTANTIATE_TEST_SUITE_P(Walls, WaterReflection,
                         ::testing::Values(ReflectionCase{SurfaceMode::vertical_only, NodeConstraint::fixed},
                                           ReflectionCase{SurfaceMode::vertical_only, NodeConstraint::vertical_only},
                                           ReflectionCase{SurfaceMode::full_3d, NodeConstraint::fixed},
                                           ReflectionCase{SurfaceMode::full_3d, NodeConstraint::vertical_only}),
                         [](const ::testing::TestParamInfo<ReflectionCase>& c) {
                           return std::string(c.param.mode == SurfaceMode::full_3d ? "Full3d" : "VerticalOnly") +
                                  (c.param.wall == NodeConstraint::fixed ? "_FixedEdge" : "_VerticalOnlyWall");
                         });

}  // namespace
