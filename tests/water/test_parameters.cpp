#include <gtest/gtest.h>

#include <cmath>

#include "shore/core/error.h"
#include "shore/water/parameters.h"

using namespace shore::water;

TEST(WaterParameters, PhysicalDepthGivesShallowWaterSpeed) {
  PhysicalParameters p;
  p.depth = 0.5;
  p.cell = 0.05;
  const LatticeParameters l = p.to_lattice();
  EXPECT_NEAR(l.wave_speed(), std::sqrt(9.81 * 0.5), 1e-12);  // 2.215 m/s
  EXPECT_NEAR(l.mass, 1000 * 0.05 * 0.05 * 0.5, 1e-12);
  EXPECT_NEAR(l.damping_time(), p.damping_time, 1e-12);
}

TEST(WaterParameters, PaperPresetAndValidation) {
  const LatticeParameters paper = LatticeParameters::paper();
  EXPECT_NEAR(paper.wave_speed(), std::sqrt(3 * 7 * 0.1 / 4.0), 1e-12);
  LatticeParameters bad = paper;
  bad.mass = -1;
  EXPECT_THROW(bad.validate(), shore::InvalidSetting);
  PhysicalParameters pbad;
  pbad.rest_ratio = 1.0;
  EXPECT_THROW(pbad.validate(), shore::InvalidSetting);
}
