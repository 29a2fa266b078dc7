// Layers in depth through the Bullet coupling: a plate released on a packed crust thicker
// than it sinks comes to rest as on packed sand alone; released on a thin crust it breaks
// through to where the two-piece Bekker law's work equals the plate's (p z = integral of
// p(s) ds over its sinkage, the released plate's balance on rigid-plastic soil, solved
// here with std::pow).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "shore/scenes/soil_cases.h"
#include "shore/terrain/terrain.h"

using namespace shore;
using namespace shore::scenes;

namespace {

terrain::Material packed() {
  terrain::Material m = terrain::Material::sand();
  m.name = "packed";
  m.bekker_kphi *= 4.0;
  m.unload_modulus = 0.0;
  return m;
}

/// The plate (0.3 m, 50 kPa, released) on sand painted packed, layered over sand `crust`
/// m below the top (crust < 0: packed alone, no layer).
PlateResult plate(double crust) {
  PlateCase c;
  c.settle_seconds = 0.5;
  c.run.terrain.material.unload_modulus = 0.0;  // rigid-plastic: the work balance is exact
  c.run.prepare = [crust](terrain::Terrain& soil) {
    soil.set_palette({soil.settings().material, packed()});
    soil.paint_rect({-200, -200, 400, 400}, 1);
    if (crust >= 0.0) soil.paint_layer_rect({-200, -200, 400, 400}, 0, crust);
  };
  return run_plate(c);
}

/// The two-piece law (packed over sand, boundary d) for a plate of width b, Pa.
double two_piece(double d, double b, double z) {
  const auto piece = [b](const terrain::Material& m, double s) {
    return s <= 0.0 ? 0.0 : (m.bekker_kc / b + m.bekker_kphi) * std::pow(s, m.bekker_n);
  };
  return z <= d ? piece(packed(), z) : piece(packed(), d) + piece(terrain::Material::sand(), z - d);
}

/// The released plate's sinkage: p z = integral of two_piece over [0, z] (the soil's
/// plastic work equals the weight's), by bisection with a 2000-strip midpoint integral.
double released_sinkage(double d, double b, double p) {
  const auto excess = [&](double z) {
    double work = 0.0;
    constexpr int kStrips = 2000;
    for (int k = 0; k < kStrips; ++k) work += two_piece(d, b, (k + 0.5) * z / kStrips);
    return work * z / kStrips - p * z;
  };
  double lo = 1e-6, hi = 0.5;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (excess(mid) < 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

TEST(SoilLayers, APlateOnAThickCrustRestsAsOnTheCrustAloneAndBreaksThroughAThinOne) {
  const PlateResult alone = plate(-1.0), thick = plate(0.2), thin = plate(0.005);
  const double ref_thin = released_sinkage(0.005, 0.3, 50e3);
  const double ref_alone = released_sinkage(1.0, 0.3, 50e3);
  std::printf(
      "released plate at 50 kPa: packed alone %.3f mm (Bekker released %.3f), 20 cm crust %.3f mm; 5 mm crust "
      "%.3f mm (two-piece released %.3f)\n",
      1e3 * alone.sinkage, 1e3 * ref_alone, 1e3 * thick.sinkage, 1e3 * thin.sinkage, 1e3 * ref_thin);
  EXPECT_NEAR(alone.sinkage, ref_alone, 0.03 * ref_alone);
  EXPECT_EQ(thick.sinkage, alone.sinkage);  // within the crust the law is the crust's, bit for bit
  ASSERT_GT(thin.sinkage, 0.005);           // broken through
  EXPECT_NEAR(thin.sinkage, ref_thin, 0.03 * ref_thin);
  EXPECT_EQ(thin.stats.rescues, 0);
}

}  // namespace
