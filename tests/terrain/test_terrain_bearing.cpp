// Bekker's plate sinkage from the column model under slow loading, plastic memory,
// rigid ground and bedrock.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "shore/terrain/bekker.h"
#include "shore/terrain/terrain.h"
#include "terrain_fixtures.h"

using namespace shore::terrain;
using namespace shore::terrain::testing;

namespace {

constexpr int kPlate = 30;  // 0.3 m x 0.3 m at 1 cm: columns [-15, 15)

// Ramps the plate load from 0 to `load` over `steps` steps; each step lowers the plate by
// the bearing offset for the current load and presses it in. Returns the plate's depth.
double ramp_plate(Terrain& t, double load, int steps, double start_depth = 0.0) {
  double depth = start_depth;
  for (int k = 1; k <= steps; ++k) {
    const double f = load * k / steps;
    const shore::EnvelopeRaster here = box_envelope(-15, -15, kPlate, kPlate, -depth);
    depth += t.bearing_offset(here, f);
    const shore::EnvelopeRaster env = box_envelope(-15, -15, kPlate, kPlate, -depth);
    const Imprint im{&env};
    t.step({&im, 1});
  }
  return depth;
}

TerrainSettings settings_for(const Material& m) {
  TerrainSettings s;
  s.material = m;
  return s;
}

}  // namespace

TEST(Bearing, PlateOnDrySandSinksAsBekker) {
  Terrain t(settings_for(Material::sand()));
  const double p = 50e3, area = 0.3 * 0.3;
  const double depth = ramp_plate(t, p * area, 20);
  const double ref = bekker::plate_sinkage(Material::sand(), 0.3, p);
  EXPECT_NEAR(ref, 0.0446, 0.0001);  // the design's reference value
  EXPECT_NEAR(depth, ref, 0.02 * ref);
  const shore::EnvelopeRaster env = box_envelope(-15, -15, kPlate, kPlate, -depth);
  const Bearing b = t.bearing(env);
  EXPECT_DOUBLE_EQ(b.patch_width, 0.3);
  EXPECT_EQ(b.contact_columns, kPlate * kPlate);
  double sum = 0.0;
  for (const auto& c : b.columns) sum += c.force;
  EXPECT_NEAR(sum, b.capacity, 1e-9 * b.capacity);
  EXPECT_NEAR(b.capacity, p * area, 0.01 * p * area);
}

TEST(Bearing, MudAndSnowAtTwoLoads) {
  struct Case {
    Material m;
    double p;
  };
  for (const Case& c : {Case{Material::mud(), 20e3}, Case{Material::mud(), 60e3}, Case{Material::snow(), 8e3},
                        Case{Material::snow(), 16e3}}) {
    Terrain t(settings_for(c.m));
    const double depth = ramp_plate(t, c.p * 0.09, 20);
    const double ref = bekker::plate_sinkage(c.m, 0.3, c.p);
    EXPECT_NEAR(depth, ref, 0.02 * ref) << c.m.name << " at " << c.p << " Pa";
  }
}

TEST(Bearing, PlasticMemoryReloadingSinksNoFurther) {
  Terrain t(settings_for(Material::sand()));
  const double load = 30e3 * 0.09;
  const double depth = ramp_plate(t, load, 10);
  std::vector<double> under;  // heights and sinkage under the plate
  for (std::int64_t j = -15; j < 15; ++j)
    for (std::int64_t i = -15; i < 15; ++i) under.push_back(t.height(i, j)), under.push_back(t.sinkage(i, j));
  // Unload (nothing happens to plastic soil) and load again to the same pressure.
  const shore::EnvelopeRaster env = box_envelope(-15, -15, kPlate, kPlate, -depth);
  EXPECT_EQ(t.bearing_offset(env, load), 0.0);
  const Imprint im{&env};
  t.step({&im, 1});
  std::size_t k = 0;
  for (std::int64_t j = -15; j < 15; ++j)
    for (std::int64_t i = -15; i < 15; ++i, k += 2) {
      ASSERT_EQ(t.height(i, j), under[k]);
      ASSERT_EQ(t.sinkage(i, j), under[k + 1]);
    }
  // A higher load continues the Bekker curve from where the soil was left.
  const double deeper = ramp_plate(t, 2 * load, 10, depth);
  const double ref = bekker::plate_sinkage(Material::sand(), 0.3, 60e3);
  EXPECT_NEAR(deeper, ref, 0.02 * ref);
}

TEST(Bearing, BearingOffsetMatchesBekkerInOneStep) {
  // A fresh plate on flat ground: capacity(offset) = (k_c/b + k_phi) offset^n * area.
  Terrain t(settings_for(Material::sand()));
  const shore::EnvelopeRaster env = box_envelope(-15, -15, kPlate, kPlate, 0.0);
  const double load = 40e3 * 0.09;
  const double offset = t.bearing_offset(env, load);
  EXPECT_NEAR(offset, bekker::plate_sinkage(Material::sand(), 0.3, 40e3), 2e-7);
  EXPECT_GE(t.bearing(env, offset).capacity, load);
  EXPECT_EQ(t.tile_count(), 0u);  // bearing only reads
}

TEST(Bearing, RigidGroundCarriesAnythingAndNeverDeforms) {
  Terrain t(settings_for(Material::rigid_ground()));
  const std::uint64_t before = t.state_hash();
  const shore::EnvelopeRaster env = box_envelope(-15, -15, kPlate, kPlate, -0.05);
  EXPECT_EQ(t.bearing(env).capacity, std::numeric_limits<double>::infinity());
  EXPECT_EQ(t.bearing_offset(env, 1e9), 0.0);
  const Imprint im{&env};
  const StepReport r = t.step({&im, 1});
  EXPECT_EQ(r.contact_columns, 0);
  EXPECT_EQ(t.state_hash(), before);
  EXPECT_EQ(t.height(0, 0), 0.0);
}

TEST(Bearing, NothingGoesBelowBedrockWhichCarriesAnything) {
  Material m = Material::snow();
  m.soil_depth = 0.02;
  Terrain t(settings_for(m));
  const shore::EnvelopeRaster deep = box_envelope(-15, -15, kPlate, kPlate, -0.05);
  const Imprint im{&deep};
  t.step({&im, 1});
  EXPECT_DOUBLE_EQ(t.height(0, 0), -0.02);
  EXPECT_DOUBLE_EQ(t.bedrock(0, 0), -0.02);
  EXPECT_EQ(t.bearing(deep).capacity, std::numeric_limits<double>::infinity());
  // From the surface, no load sinks a plate deeper than the soil.
  Terrain fresh(settings_for(m));
  const shore::EnvelopeRaster top = box_envelope(-15, -15, kPlate, kPlate, 0.0);
  const double o = fresh.bearing_offset(top, 1e12);
  EXPECT_LE(o, 0.02 + 1e-12);
  EXPECT_GT(o, 0.02 - 1e-6);
}
