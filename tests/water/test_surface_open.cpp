// Open boundaries: a ring's echo from an open edge (the absorbing layer of
// OpenBoundarySettings) against the echo from a fixed edge and from a vertical-only wall.
// The echo is measured at the source as the difference from a run whose edges are too far
// to echo within the window (so the ring's own 2-D tail cancels), against the ring's
// amplitude at the distance the echo travelled (what a perfect mirror returns).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "shore/core/error.h"
#include "shore/water/surface.h"

using namespace shore::water;

namespace {

constexpr double kCell = 0.05, kSigma = 0.1, kAmplitude = 1e-3, kDt = 1.0 / 240;
constexpr int kDistance = 30;  // nodes from the source to the edge of the water

struct Echo {
  double reflected = 0.0;  ///< largest echo at the source, m
  double direct = 0.0;     ///< the ring's amplitude at twice the distance, m
  [[nodiscard]] double ratio() const { return reflected / direct; }
};

SurfaceSettings patch(SurfaceMode mode, Boundary b, int margin_west, int nx, int ny) {
  PhysicalParameters p;
  p.cell = kCell;
  p.depth = 0.5;
  p.damping_time = std::numeric_limits<double>::infinity();
  SurfaceSettings s = SurfaceSettings::physical(p, nx, ny);
  s.mode = mode;
  s.boundary = b;
  s.threads = 1;
  s.origin_x = -kCell * margin_west;  // the source sits at x = 0
  s.origin_y = -kCell * (ny / 2);
  return s;
}

/// Heights at the source (x = 0) and at x = 2 d over the echo's window.
struct Trace {
  std::vector<double> source, probe;
};
Trace run(const SurfaceSettings& s, double window_end) {
  Surface surf(s);
  surf.disturb(Disturbance::point_height(0.0, 0.0, kSigma, kAmplitude));
  const double cw = s.lattice.wave_speed(), d = kDistance * kCell;
  Trace t;
  for (int k = 1; k * kDt * cw < window_end; ++k) {
    surf.step(kDt);
    if (k * kDt * cw < 2.0 * d - 5.0 * kSigma) continue;  // before any echo can arrive
    t.source.push_back(surf.height_at(0.0, 0.0));
    t.probe.push_back(surf.height_at(2.0 * d, 0.0));
  }
  return t;
}

/// The echo of the west edge of the water, kDistance nodes from the source: for an open
/// edge the layer lies beyond it.
Echo echo(SurfaceMode mode, Boundary b) {
  const int layer = b == Boundary::open ? OpenBoundarySettings{}.width : 0;
  const int west = kDistance + layer, ny = 2 * (2 * kDistance + layer) + 21;
  const double window_end = 2.0 * (kDistance + layer) * kCell + 6.0 * kSigma;  // echoes from deep in the layer too
  const Trace with_edge = run(patch(mode, b, west, west + 3 * kDistance + layer, ny), window_end);
  const int far = std::max(kDistance + layer, 2 * kDistance) + 20;  // no echo within the window
  const Trace free_space = run(patch(mode, Boundary::vertical_only, far, 2 * far, 2 * far + 1), window_end);
  Echo e;
  for (std::size_t k = 0; k < with_edge.source.size(); ++k) {
    e.reflected = std::max(e.reflected, std::abs(with_edge.source[k] - free_space.source[k]));
    e.direct = std::max(e.direct, std::abs(free_space.probe[k]));
  }
  return e;
}

std::string name(SurfaceMode m) { return m == SurfaceMode::full_3d ? "Full3d" : "VerticalOnly"; }

class OpenEdge : public ::testing::TestWithParam<SurfaceMode> {};

TEST_P(OpenEdge, EchoesUnderFivePercentWhereWallsEchoInFull) {
  const Echo open = echo(GetParam(), Boundary::open);
  const Echo fixed = echo(GetParam(), Boundary::fixed);
  const Echo wall = echo(GetParam(), Boundary::vertical_only);
  ASSERT_GT(open.direct, 0.02 * kAmplitude);
  EXPECT_LT(open.ratio(), 0.05) << "open edge echo " << open.reflected << " of " << open.direct;
  EXPECT_GT(fixed.ratio(), 0.9) << "fixed edge";
  EXPECT_GT(wall.ratio(), 0.9) << "vertical-only wall";
  RecordProperty("open_echo", std::to_string(open.ratio()));
  RecordProperty("fixed_echo", std::to_string(fixed.ratio()));
  RecordProperty("wall_echo", std::to_string(wall.ratio()));
}

INSTANTIATE_TEST_SUITE_P(Modes, OpenEdge, ::testing::Values(SurfaceMode::vertical_only, SurfaceMode::full_3d),
                         [](const ::testing::TestParamInfo<SurfaceMode>& c) { return name(c.param); });

TEST(OpenEdge, LayerMustLeaveWater) {
  SurfaceSettings s = patch(SurfaceMode::vertical_only, Boundary::open, 0, 40, 40);
  EXPECT_THROW(Surface{s}, shore::InvalidSetting);  // 2 * 32 >= 40
  s.open.width = 8;
  EXPECT_NO_THROW(Surface{s});
  s.open.strength = 0.0;
  EXPECT_THROW(Surface{s}, shore::InvalidSetting);
}

}  // namespace
