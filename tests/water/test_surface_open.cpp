// Open boundaries: a ring's echo from an open edge (the absorbing layer of
// OpenBoundarySettings) against the echo from a fixed edge and from a vertical-only wall
// (the case and its reference: scenes/include/shore/scenes/water_cases.h). The echo is
// measured at the source as the difference from a run whose edges are too far to echo
// within the window (so the ring's own 2-D tail cancels), against the ring's amplitude at
// the distance the echo travelled (what a perfect mirror returns).

#include <gtest/gtest.h>

#include <string>

#include "shore/core/error.h"
#include "shore/scenes/water_cases.h"
#include "shore/water/surface.h"

using namespace shore::water;
using shore::scenes::EchoCase;
using shore::scenes::measure_echo;

namespace {

std::string name(SurfaceMode m) { return m == SurfaceMode::full_3d ? "Full3d" : "VerticalOnly"; }

class OpenEdge : public ::testing::TestWithParam<SurfaceMode> {};

TEST_P(OpenEdge, EchoesUnderFivePercentWhereWallsEchoInFull) {
  const auto echo = [](SurfaceMode m, Boundary b) { return measure_echo(EchoCase{.mode = m, .boundary = b}); };
  const auto open = echo(GetParam(), Boundary::open);
  const auto fixed = echo(GetParam(), Boundary::fixed);
  const auto wall = echo(GetParam(), Boundary::vertical_only);
  ASSERT_GT(open.direct, 2e-5) << "the ring never reached the probe";
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
  SurfaceSettings s = SurfaceSettings::physical(PhysicalParameters{}, 40, 40);
  s.boundary = Boundary::open;
  EXPECT_THROW(Surface{s}, shore::InvalidSetting);  // 2 * 32 >= 40
  s.open.width = 8;
  EXPECT_NO_THROW(Surface{s});
  s.open.strength = 0.0;
  EXPECT_THROW(Surface{s}, shore::InvalidSetting);
}

}  // namespace
