// Bad input (clear errors, state untouched), queries, mesh and normals.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "shore/core/error.h"
#include "shore/water/stability.h"
#include "shore/water/surface.h"

using namespace shore::water;
using shore::InvalidSetting;

namespace {

/// Expects an InvalidSetting whose field and message name the field and the value.
template <class Fn>
void expect_invalid(Fn&& fn, const std::string& field, const std::string& value) {
  try {
    fn();
    ADD_FAILURE() << "no error for " << field;
  } catch (const InvalidSetting& e) {
    EXPECT_EQ(e.field(), field);
    EXPECT_NE(std::string(e.what()).find(value), std::string::npos) << e.what();
  }
}

TEST(WaterInput, BadSettingsAreRejectedByName) {
  const auto build = [](auto change) {
    return [change] {
      SurfaceSettings s;
      change(s);
      Surface surf(s);
    };
  };
  expect_invalid(build([](SurfaceSettings& s) { s.lattice.mass = 0.0; }), "water.LatticeParameters.mass", "0");
  expect_invalid(build([](SurfaceSettings& s) { s.lattice.mass = -4.0; }), "water.LatticeParameters.mass", "-4");
  expect_invalid(build([](SurfaceSettings& s) { s.lattice.stiffness = -7.0; }), "water.LatticeParameters.stiffness",
                 "-7");
  expect_invalid(build([](SurfaceSettings& s) { s.lattice.spacing = 0.0; }), "water.LatticeParameters.spacing", "0");
  expect_invalid(build([](SurfaceSettings& s) { s.nx = 2; }), "water.SurfaceSettings.nx", "2");
  expect_invalid(build([](SurfaceSettings& s) { s.ny = 1; }), "water.SurfaceSettings.ny", "1");
  expect_invalid(build([](SurfaceSettings& s) { s.lattice.damping = std::nan(""); }), "water.LatticeParameters.damping",
                 "nan");
  expect_invalid(build([](SurfaceSettings& s) { s.guard.safety = 1.5; }), "water.GuardSettings.safety", "1.5");
  PhysicalParameters p;
  p.cell = -0.05;
  expect_invalid([&] { (void)p.to_lattice(); }, "water.PhysicalParameters.cell", "-0.05");
}

TEST(WaterInput, BadStepsAndDisturbancesLeaveTheStateUntouched) {
  Surface surf(SurfaceSettings::paper());
  surf.disturb(Disturbance::point_height(20.0, 20.0, 2.0, 0.5));
  surf.step(0.4);
  const std::uint64_t before = surf.state_hash();
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  expect_invalid([&] { surf.step(0.0); }, "water.Surface.step.dt", "0");
  expect_invalid([&] { surf.step(-0.4); }, "water.Surface.step.dt", "-0.4");
  expect_invalid([&] { surf.step(nan); }, "water.Surface.step.dt", "nan");
  expect_invalid([&] { surf.disturb(Disturbance::point_height(nan, 1.0, 1.0, 1.0)); }, "water.Disturbance.x", "nan");
  expect_invalid([&] { surf.disturb(Disturbance::point_velocity(1.0, 1.0, 1.0, inf)); }, "water.Disturbance.amplitude",
                 "inf");
  expect_invalid([&] { surf.disturb(Disturbance::point_height(1.0, 1.0, 0.0, 1.0)); }, "water.Disturbance.radius", "0");
  expect_invalid([&] { surf.disturb(Disturbance::point_height(1.0, 1.0, 1.0, 1e9)); }, "water.Disturbance.amplitude",
                 "1000000000");
  // A batch with one bad entry applies none of them.
  const std::vector<Disturbance> batch = {Disturbance::point_height(10.0, 10.0, 2.0, 1.0),
                                          Disturbance::point_height(10.0, 10.0, -2.0, 1.0)};
  expect_invalid([&] { surf.disturb(batch); }, "water.Disturbance.radius", "-2");
  expect_invalid([&] { surf.add_height(3, 3, nan); }, "water.Surface.add_height.dz", "nan");
  expect_invalid([&] { surf.add_vertical_velocity(3, 3, inf); }, "water.Surface.add_vertical_velocity.dv", "inf");
  expect_invalid([&] { (void)surf.height(50, 3); }, "water.Surface.height.i", "50");
  EXPECT_EQ(surf.state_hash(), before);
}

// Edits within the caps, repeated without limit between steps, would drive a node beyond the
// range where the exact sums hold (a restored corrupt state can start there too): the state
// saturates at its documented range, stays finite, and the row sums never overflow (UBSan).
TEST(WaterInput, RunawayEditsSaturateAtTheStatesRange) {
  for (const SurfaceMode mode : {SurfaceMode::full_3d, SurfaceMode::vertical_only}) {
    SurfaceSettings set = SurfaceSettings::paper();
    set.mode = mode;
    Surface surf(set);
    const double h = surf.spacing();
    const double omega =
        mode == SurfaceMode::full_3d ? omega_max_at_rest(set.lattice) : omega_max_vertical(set.lattice);
    const double dz = set.guard.max_disturbance_spacings * h, dv = dz * omega;  // the caps
    for (int k = 0; k < 64; ++k)
      for (int j = 8; j < 12; ++j)
        for (int i = 8; i < 12; ++i) {
          const double sign = (i + j) % 2 ? 1.0 : -1.0;
          surf.add_height(i, j, sign * dz);
          surf.add_vertical_velocity(i, j, -sign * dv);
        }
    // 64 caps is beyond 2^50 height quanta (at most 4096 spacings) and 2^49 velocity quanta.
    EXPECT_LE(std::abs(surf.height(9, 9) - surf.height(0, 0)), 4096.0 * h);
    EXPECT_GT(std::abs(surf.height(9, 9) - surf.height(0, 0)), 2000.0 * h);
    for (int step = 0; step < 20; ++step) surf.step(1.0 / 60.0);
    double top = 0.0;
    for (int j = 0; j < surf.ny(); ++j)
      for (int i = 0; i < surf.nx(); ++i) {
        ASSERT_TRUE(std::isfinite(surf.height(i, j)) && std::isfinite(surf.vertical_velocity(i, j)));
        EXPECT_LE(std::abs(surf.vertical_velocity(i, j)), 2048.0 * h * omega);
        top = std::max(top, std::abs(surf.height(i, j) - surf.height(0, 0)));
      }
    EXPECT_LE(top, 4096.0 * h);
    EXPECT_TRUE(std::isfinite(surf.volume()));
  }
}

TEST(WaterQueries, NodeAndWorldHelpersAgree) {
  SurfaceSettings s;
  s.nx = 8;
  s.ny = 6;
  s.origin_x = 10.0;
  s.origin_y = -3.0;
  s.rest_height = 2.5;
  s.lattice.spacing = 0.5;
  Surface surf(s);
  EXPECT_DOUBLE_EQ(surf.node_x(3), 11.5);
  EXPECT_DOUBLE_EQ(surf.node_y(2), -2.0);
  EXPECT_DOUBLE_EQ(surf.height(4, 4), 2.5);
  const Eigen::Vector2d g = surf.grid_coordinates(11.25, -2.0);
  EXPECT_DOUBLE_EQ(g.x(), 2.5);
  EXPECT_DOUBLE_EQ(g.y(), 2.0);
  ASSERT_TRUE(surf.nearest_node(11.3, -2.1).has_value());
  EXPECT_EQ(surf.nearest_node(11.3, -2.1)->i, 3);
  EXPECT_EQ(surf.nearest_node(11.3, -2.1)->j, 2);
  EXPECT_FALSE(surf.nearest_node(9.0, 0.0).has_value());
  EXPECT_TRUE(surf.contains(10.0, -3.0));
  EXPECT_FALSE(surf.contains(13.6, 0.0));
  // A plane z = 0.1 i + 0.2 j on the interior nodes: bilinear interpolation reproduces
  // planes exactly.
  for (int j = 1; j < 5; ++j)
    for (int i = 1; i < 7; ++i) EXPECT_TRUE(surf.add_height(i, j, 0.1 * i + 0.2 * j));
  const double x = surf.node_x(2) + 0.3 * 0.5, y = surf.node_y(3) + 0.6 * 0.5;
  EXPECT_NEAR(surf.height_at(x, y), 2.5 + 0.1 * 2.3 + 0.2 * 3.6, 1e-6);
  // Fixed edge nodes refuse edits.
  EXPECT_FALSE(surf.add_height(0, 0, 1.0));
  EXPECT_TRUE(surf.is_fixed(0, 0));
  surf.set_fixed(3, 3, true);
  EXPECT_FALSE(surf.add_vertical_velocity(3, 3, 1.0));
  surf.set_fixed(3, 3, false);
  EXPECT_TRUE(surf.add_vertical_velocity(3, 3, 1.0));
  EXPECT_DOUBLE_EQ(surf.vertical_velocity(3, 3), 1.0);
  EXPECT_NEAR(surf.vertical_velocity_at(surf.node_x(3), surf.node_y(3)), 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(surf.density(), 1000.0);
}

TEST(WaterQueries, FixedNodesStayPutUnderDisturbancesAndSteps) {
  Surface surf(SurfaceSettings::paper());
  for (int j = 20; j < 25; ++j)
    for (int i = 20; i < 25; ++i) surf.set_fixed(i, j, true);
  surf.disturb(Disturbance::area_velocity(22.0, 22.0, 10.0, 10.0, 1.0, 1.0));
  for (int k = 0; k < 50; ++k) surf.step(0.4);
  EXPECT_EQ(surf.position(22, 22), Eigen::Vector3d(22.0, 22.0, 0.0));
  EXPECT_NE(surf.height(10, 22), 0.0);
}

TEST(WaterMesh, PaperTriangulationCountsAndWinding) {
  std::vector<std::uint32_t> idx;
  triangulate(50, 50, idx);
  EXPECT_EQ(idx.size() / 3, 4802u);  // the paper's count for 50 x 50
  // Every triangle counter-clockwise seen from +Z, and every cell covered by two triangles
  // of total area h^2 (no overlap, no gap).
  double area = 0.0;
  for (std::size_t t = 0; t < idx.size(); t += 3) {
    const auto xy = [](std::uint32_t v) { return Eigen::Vector2d(v % 50, v / 50); };
    const Eigen::Vector2d a = xy(idx[t]), b = xy(idx[t + 1]), c = xy(idx[t + 2]);
    const double cross = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    EXPECT_GT(cross, 0.0);
    area += 0.5 * cross;
  }
  EXPECT_DOUBLE_EQ(area, 49.0 * 49.0);
}

TEST(WaterMesh, NormalsOfATiltedPlane) {
  SurfaceSettings s;
  s.nx = s.ny = 6;
  s.boundary = Boundary::free;
  s.mode = SurfaceMode::vertical_only;
  Surface surf(s);
  const double slope = 0.25;  // z = slope * x
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i) surf.add_height(i, j, slope * surf.node_x(i));
  std::vector<float> n;
  surf.normals(n);
  const double len = std::sqrt(1.0 + slope * slope);
  for (std::size_t k = 0; k < 36; ++k) {
    EXPECT_NEAR(n[3 * k + 0], -slope / len, 1e-6);
    EXPECT_NEAR(n[3 * k + 1], 0.0, 1e-6);
    EXPECT_NEAR(n[3 * k + 2], 1.0 / len, 1e-6);
  }
  std::vector<float> p;
  surf.positions(p);
  EXPECT_FLOAT_EQ(p[3 * 7 + 0], 1.0f);
  EXPECT_FLOAT_EQ(p[3 * 7 + 1], 1.0f);
  EXPECT_FLOAT_EQ(p[3 * 7 + 2], static_cast<float>(slope));
}

TEST(WaterEnergyDefinition, SpringPotentialOfOneRaisedNode) {
  // One interior node raised by a in vertical-only mode: 8 springs, each stretched across by
  // a, linearised energy k_t a^2 / 2 each, k_t = c (1 - rest_ratio).
  SurfaceSettings s;
  s.nx = s.ny = 5;
  s.mode = SurfaceMode::vertical_only;
  Surface surf(s);
  const double a = 0.1;
  surf.add_height(2, 2, a);
  const double kt = s.lattice.stiffness * (1.0 - s.lattice.rest_ratio);
  EXPECT_NEAR(surf.energy().potential, 8 * 0.5 * kt * a * a, 1e-9);
  // 3-D: exact spring energies c/2 [(l - L0)^2 - (l_rest - L0)^2] over the 8 springs.
  s.mode = SurfaceMode::full_3d;
  Surface full(s);
  full.add_height(2, 2, a);
  const double c = s.lattice.stiffness, h = s.lattice.spacing, r = s.lattice.rest_ratio;
  double expected = 0.0;
  for (double l0 : {h, std::sqrt(2.0) * h}) {
    const double rest = r * l0, l = std::sqrt(l0 * l0 + a * a);
    expected += 4 * 0.5 * c * ((l - rest) * (l - rest) - (l0 - rest) * (l0 - rest));
  }
  EXPECT_NEAR(full.energy().potential, expected, 1e-7);
  full.add_vertical_velocity(2, 2, 0.3);
  EXPECT_NEAR(full.energy().kinetic, 0.5 * s.lattice.mass * 0.09, 1e-7);
}

}  // namespace
