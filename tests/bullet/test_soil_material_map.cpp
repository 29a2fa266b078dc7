// The Bullet coupling shears each column by its own material (the terrain's material map):
// a box sliding down a soft slope painted with soils of different friction angles slides at
// Coulomb's rate for the soil under it, and across a border by both soils together.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "shore/scenes/soil_cases.h"
#include "shore/scenes/wong_reece.h"
#include "shore/terrain/terrain.h"

using namespace shore;
using namespace shore::scenes;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kGravity = 9.81;
constexpr double kSlope = 35 * kDeg;

double rel(double got, double want) { return std::abs(got - want) / std::abs(want); }

/// Sand without softening or cohesion, with Wong's elastic unloading (a box then slides at
/// Coulomb's rate, tests/bullet/test_soil_contact.cpp), of friction angle phi.
terrain::Material coulomb_soil(double phi_deg) {
  terrain::Material m = terrain::Material::sand();
  m.alpha = 0.0;
  m.remould_ratio = m.remould_shear_ratio = 0.0;
  m.cohesion = 0.0;
  m.unload_modulus = 5e8;
  m.friction_angle = phi_deg * kDeg;
  return m;
}

const terrain::Material kFirm = coulomb_soil(28.0);
const terrain::Material kLoose = coulomb_soil(18.0);

/// Coulomb's acceleration down the slope for a mean friction coefficient tan_phi.
double coulomb(double tan_phi) { return kGravity * (std::sin(kSlope) - tan_phi * std::cos(kSlope)); }

/// The box's columns and its path downhill (+x): 0.3 m box, 1 cm columns.
const GridRect kPath{-60, -60, 600, 120};

/// A 0.3 m box released on the slope; entry 0 of the soil is `base`, and `paint` (if set)
/// makes the palette {base, other} and paints where it says.
SlopeBoxResult slide(const terrain::Material& base, const terrain::Material* other = nullptr,
                     bool (*inside)(double x, double y) = nullptr) {
  SlopeBoxCase c;
  c.slope = kSlope;
  c.run.terrain.material = base;
  c.run.body_spray = false;
  if (other != nullptr)
    c.run.prepare = [other, inside](terrain::Terrain& soil) {
      soil.set_palette({soil.settings().material, *other});
      soil.paint_where(kPath, inside, 1);
    };
  return run_slope_box(c);
}

TEST(SoilMaterialMap, ABoxSlidesAsOnTheSoilPaintedUnderIt) {
  // Entry 0 firm, the whole path painted loose: it slides as on loose soil alone (the same
  // bits: each block is of one material), at Coulomb's rate for loose soil, not firm's.
  // And the other way round.
  const auto everywhere = [](double, double) { return true; };
  for (const bool loose_painted : {true, false}) {
    const terrain::Material& base = loose_painted ? kFirm : kLoose;
    const terrain::Material& painted = loose_painted ? kLoose : kFirm;
    const SlopeBoxResult alone = slide(painted);
    const SlopeBoxResult on_map = slide(base, &painted, everywhere);
    const double want = coulomb(std::tan(painted.friction_angle));
    EXPECT_EQ(on_map.acceleration, alone.acceleration) << "painted " << (loose_painted ? "loose" : "firm");
    EXPECT_EQ(on_map.distance, alone.distance);
    EXPECT_LT(rel(on_map.acceleration, want), 0.10) << on_map.acceleration << " vs Coulomb " << want;
    std::printf("painted %s: %.4f m/s^2 (alone %.4f, Coulomb %.4f)\n", loose_painted ? "loose" : "firm",
                on_map.acceleration, alone.acceleration, want);
    const double other = coulomb(std::tan(base.friction_angle));
    EXPECT_GT(std::abs(on_map.acceleration - other), 0.5 * std::abs(want - other)) << "slides as on entry 0";
  }
}

TEST(SoilMaterialMap, ABoxAcrossBordersSlidesByBothSoils) {
  // Loose soil in a stripe down the slope under the box's middle (|y| < 7.5 cm: its 15
  // middle columns), firm beside it (its other 15, the edge columns half covered), so the
  // two soils turn it neither way. The stripe's edges do not all lie on blocks' edges: some
  // blocks hold both soils. Coulomb's friction is the sum over both parts at the same
  // pressure: the mean of the two tan(phi).
  const SlopeBoxResult r = slide(kFirm, &kLoose, [](double, double y) { return std::abs(y) < 0.075; });
  const double tan_firm = std::tan(kFirm.friction_angle), tan_loose = std::tan(kLoose.friction_angle);
  const double want = coulomb(0.5 * (tan_firm + tan_loose));
  EXPECT_LT(rel(r.acceleration, want), 0.10) << r.acceleration << " vs Coulomb " << want;
  std::printf("loose stripe under the middle: %.4f m/s^2 (Coulomb %.4f)\n", r.acceleration, want);
  // Clearly between the soils alone (Coulomb: firm 1.35, loose 3.02 m/s^2).
  EXPECT_GT(r.acceleration, 0.5 * (coulomb(tan_firm) + want));
  EXPECT_LT(r.acceleration, 0.5 * (coulomb(tan_loose) + want));
  EXPECT_LT(r.max_tilt, 5 * kDeg);
}

TEST(SoilMaterialMap, ADrivenWheelPullsAsWongAndReecePredictForThePaintedSoil) {
  // Entry 0 shears weakly (c 0, phi 15 deg, K 5 cm); the wheel's path is painted with Wong's
  // dry sand (c, phi, K, remoulding all the sand's): it pulls and sinks as on sand alone,
  // bit for bit, within the Wong-Reece tolerances of the one-soil test
  // (SoilContact.ADrivenWheelPullsAndSinksAsWongAndReecePredict).
  terrain::Material weak = terrain::Material::sand();
  weak.cohesion = 0.0;
  weak.friction_angle = 15 * kDeg;
  weak.shear_modulus = 0.05;
  DrivenWheelCase c;
  c.slip = 0.2;
  const DrivenWheelResult alone = run_driven_wheel(c);
  const terrain::Material sand = c.run.terrain.material;
  c.run.terrain.material = weak;
  const DrivenWheelResult on_weak = run_driven_wheel(c);
  c.run.prepare = [sand](terrain::Terrain& soil) {
    soil.set_palette({soil.settings().material, sand});
    soil.paint_rect(kPath, 1);
  };
  const DrivenWheelResult painted = run_driven_wheel(c);
  EXPECT_EQ(painted.drawbar_pull, alone.drawbar_pull);
  EXPECT_EQ(painted.torque, alone.torque);
  EXPECT_EQ(painted.sinkage, alone.sinkage);
  const WongReeceResult want = wong_reece(WongReeceWheel{}, c.slip);
  EXPECT_LT(std::abs(painted.drawbar_pull - want.drawbar_pull) / c.load, 0.08)
      << painted.drawbar_pull << " N vs Wong-Reece " << want.drawbar_pull << " N";
  EXPECT_LT(rel(painted.torque, want.torque), 0.15) << painted.torque << " N m vs " << want.torque;
  // The weak soil alone pulls far less: the test tells the soils apart.
  EXPECT_LT(on_weak.drawbar_pull, alone.drawbar_pull - 0.05 * c.load);
  std::printf(
      "driven wheel, slip 0.2: painted sand %.1f N, %.1f N m (Wong-Reece %.1f N, %.1f N m); weak entry 0 "
      "alone %.1f N\n",
      painted.drawbar_pull, painted.torque, want.drawbar_pull, want.torque, on_weak.drawbar_pull);
}

}  // namespace
