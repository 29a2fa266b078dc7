#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "shore/core/error.h"
#include "shore/terrain/material.h"

using shore::terrain::Material;

TEST(Material, PresetsAreValid) {
  for (const char* name : {"sand", "mud", "snow", "rigid"}) EXPECT_NO_THROW(Material::preset(name).validate()) << name;
  EXPECT_THROW(Material::preset("lava"), shore::InvalidSetting);
}

TEST(Material, BadValuesNameTheField) {
  Material m = Material::sand();
  m.alpha = 1.2;
  try {
    m.validate();
    FAIL();
  } catch (const shore::InvalidSetting& e) {
    EXPECT_NE(std::string(e.what()).find("alpha = 1.2"), std::string::npos) << e.what();
  }
  m = Material::sand();
  m.theta_out = 0.0;
  EXPECT_THROW(m.validate(), shore::InvalidSetting);
  m = Material::sand();
  m.theta_in = 2.0;
  EXPECT_THROW(m.validate(), shore::InvalidSetting);
  m = Material::sand();
  m.bekker_kphi = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(m.validate(), shore::InvalidSetting);
}
