// The edges of the settings ranges, smoke versions (the full ones, with their
// errors against the references, are shore-bench's reliability sweep): substeps of 1/30 s
// and 1/2000 s, cells of 2 mm and 20 cm, 0.05 kg and 50 t on snow, 50 m/s into mud. Each
// stays finite, ends above bedrock and presses the soil.
#include <gtest/gtest.h>

#include <ostream>
#include <string>

#include "shore/scenes/extreme_cases.h"

using namespace shore;

namespace shore::scenes {
// gtest prints a parameter's name, not its bytes.
void PrintTo(const ExtremeCase& c, std::ostream* os) { *os << c.name; }
}  // namespace shore::scenes

class ExtremeSettings : public ::testing::TestWithParam<scenes::ExtremeCase> {};

TEST_P(ExtremeSettings, FiniteAndNothingFallsThrough) {
  const scenes::ExtremeCase& c = GetParam();
  const scenes::ExtremeResult r = scenes::run_extreme(c);
  EXPECT_TRUE(r.finite) << c.what;
  EXPECT_TRUE(r.above_bedrock()) << c.what << ": sinkage " << r.sinkage << " m, soil " << r.soil_depth << " m";
  // Pressing is how deep it went: a ball dropped on the stiffest soil presses it a few mm
  // at the impact, which sets it rolling (it spins up to 10 rad/s), so where it ends, within
  // a mm of the surface, says nothing of it.
  EXPECT_GT(r.deepest, 0.0) << c.what << ": the body pressed the soil";
}

namespace {
std::string case_name(const ::testing::TestParamInfo<scenes::ExtremeCase>& p) { return p.param.name; }
}  // namespace

INSTANTIATE_TEST_SUITE_P(Smoke, ExtremeSettings, ::testing::ValuesIn(scenes::extreme_cases(true)), case_name);

// The unloading spring (Material::unload_modulus) with the extreme exponents: a column never
// springs back above the ground it was pressed from, so the bodies stay in the soil (without
// that bound, n = 0.05 threw its sphere 1.7 m out and the stiffest soil 357 m).
TEST(ExtremeSettingsUnloading, BodiesStayInTheSoil) {
  for (scenes::ExtremeCase c : scenes::extreme_cases(true)) {
    if (c.name != "material_n_0_05" && c.name != "material_stiffest") continue;
    c.sphere_case.run.terrain.material.unload_modulus = 5e8;
    c.plate_case.run.terrain.material.unload_modulus = 5e8;
    const scenes::ExtremeResult r = scenes::run_extreme(c);
    EXPECT_TRUE(r.finite) << c.name;
    // Thrown out it ended metres up; resting or rolling on the soil (the stiffest soil's
    // ball rolls off the pit its impact pressed) its bottom ends within a column's width of
    // the surface.
    EXPECT_GT(r.sinkage, -c.sphere_case.run.terrain.cell) << c.name << ": left the ground, " << r.sinkage << " m";
    EXPECT_GT(r.deepest, 0.0) << c.name << ": pressed the soil";
    EXPECT_TRUE(r.above_bedrock()) << c.name;
  }
}
