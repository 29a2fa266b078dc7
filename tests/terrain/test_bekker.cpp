// The closed forms against reference values worked out independently: by hand (shown next
// to each check) and with a separate integration.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

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

// Bekker's rolling sinkage integrated over the circular front arc, against his closed form
// taken exactly: on a wheel so large that the rim is the parabola z0 - x^2/D over the
// contact, the load is b k sqrt(D) z0^(n + 1/2) \int_0^1 (1 - t^2)^n dt, and that integral is
// sqrt(pi) Gamma(n+1) / (2 Gamma(n+3/2)), where the closed form has 1 - n/3. The two agree at
// n 1 and part as the exponent moves away from it (snow's 1.6, heavy clay's 0.13).
TEST(Bekker, RollingWheelFrontArcIntegralAgainstTheClosedForm) {
  const double D = 40.0, b = 0.3;  // z0 / D about 5e-4: the rim is its parabola
  for (const double n : {0.13, 0.5, 1.0, 1.6}) {
    Material m = Material::sand();
    m.bekker_n = n;
    const double W = (m.bekker_kc + b * m.bekker_kphi) * std::sqrt(D) * std::pow(0.02, n + 0.5);  // z0 about 2 cm
    const double exact = std::sqrt(std::numbers::pi) * std::tgamma(n + 1.0) / (2.0 * std::tgamma(n + 1.5));
    const double want =
        bekker::wheel_sinkage_rolling(m, W, D, b) * std::pow((3.0 - n) / 3.0 / exact, 2.0 / (2.0 * n + 1.0));
    EXPECT_NEAR(bekker::wheel_sinkage_rolling_integral(m, W, D, b) / want, 1.0, 0.003) << "n " << n;
  }
  // n 1: the closed form's 1 - n/3 is exact, so on the matrix's D 0.8 m wheel only the
  // rim's circle parts them: at z0 / D 0.06 the circle lies below the parabola by x^4/(8R^3)
  // and the integral sinks deeper.
  Material one = Material::sand();
  one.bekker_n = 1.0;
  const double closed = bekker::wheel_sinkage_rolling(one, 4000, 0.8, 0.3);
  const double integral = bekker::wheel_sinkage_rolling_integral(one, 4000, 0.8, 0.3);
  EXPECT_GT(integral, closed);
  EXPECT_LT(integral, 1.03 * closed);
}
