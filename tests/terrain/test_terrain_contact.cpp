// The soil's half of a body's contact (Terrain::contact) against closed forms: Bekker's
// pressure on a plate whatever its edges' offsets (sub-cell coverage), the plate's
// compaction resistance in the walls of its hole, the underside's normal on a cylinder;
// the shear law against Janosi-Hanamoto; loose deposits bear nothing.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <string>

#include "shore/core/error.h"
#include "shore/terrain/bekker.h"
#include "shore/terrain/shear.h"
#include "shore/terrain/terrain.h"
#include "terrain_fixtures.h"

using namespace shore::terrain;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// A flat-bottomed rectangle [x0, x1] x [y0, y1] at height bottom, seen from below.
class RectangleProbe : public SurfaceProbe {
 public:
  RectangleProbe(double x0, double y0, double x1, double y1, double bottom)
      : x0_(x0), y0_(y0), x1_(x1), y1_(y1), bottom_(bottom) {}
  [[nodiscard]] double lower_at(double x, double y) const override {
    return (x >= x0_ && x <= x1_ && y >= y0_ && y <= y1_) ? bottom_ : kInf;
  }
  /// Its envelope on the terrain's grid: the columns whose centres it covers.
  [[nodiscard]] shore::EnvelopeRaster envelope(const Terrain& t) const {
    shore::EnvelopeRaster env;
    const std::int64_t i0 = t.column_i(x0_) - 2, j0 = t.column_j(y0_) - 2;
    const std::int64_t i1 = t.column_i(x1_) + 2, j1 = t.column_j(y1_) + 2;
    env.resize(i0, j0, static_cast<int>(i1 - i0 + 1), static_cast<int>(j1 - j0 + 1), false);
    for (std::int64_t j = j0; j <= j1; ++j)
      for (std::int64_t i = i0; i <= i1; ++i) env.lower[env.index(i, j)] = lower_at(t.column_x(i), t.column_y(j));
    return env;
  }

 private:
  double x0_, y0_, x1_, y1_, bottom_;
};

struct Totals {
  double bottom_area = 0.0, bottom_force = 0.0;
  double wall_force[4] = {0.0, 0.0, 0.0, 0.0};  // pushing toward -x, +x, -y, +y
};

Totals totals(const ContactPatch& patch) {
  Totals t;
  for (const ContactElement& e : patch.elements) {
    const double f = e.pressure * e.area;
    if (!e.wall) {
      t.bottom_area += e.area;
      t.bottom_force += f * e.normal.z;
      continue;
    }
    const int side = e.normal.x < -0.5 ? 0 : e.normal.x > 0.5 ? 1 : e.normal.y < -0.5 ? 2 : 3;
    t.wall_force[side] += f;
  }
  return t;
}

TEST(Contact, PlateAreaAndBekkerPressureDoNotDependOnWhereItsEdgesFall) {
  // 0.2 m plate on 1 cm sand, its edges shifted by a fraction of a cell (0 puts them on
  // column centres: 21 x 21 columns); the soil already pressed 2 cm everywhere under it.
  const Material m = Material::sand();
  const double depth = 0.02, b = 0.2;
  for (const double shift : {0.0, 0.13, 0.25, 0.5, 0.77}) {
    TerrainSettings s;
    Terrain t(s);
    const double x0 = -0.1 + shift * s.cell, y0 = -0.1 + 0.5 * shift * s.cell;
    const RectangleProbe plate(x0, y0, x0 + b, y0 + b, -depth);
    const shore::EnvelopeRaster env = plate.envelope(t);
    ContactPatch patch;
    t.contact(env, {}, &plate, patch);
    const Totals sum = totals(patch);
    // Each edge is found to 1/64 of a cell: the width to 2/64 of a cell, the area (20 cells
    // a side) to 0.35 %.
    EXPECT_NEAR(sum.bottom_area, b * b, 3.5e-3 * b * b) << "shift " << shift;
    EXPECT_NEAR(patch.patch_width, b, s.cell / 32.0 + 1e-12) << "shift " << shift;
    const double want = bekker::pressure(m, b, depth) * b * b;
    EXPECT_NEAR(sum.bottom_force, want, 5e-3 * want) << "shift " << shift;
    // Without the probe the columns count whole: 21 x 21 of them when edges fall on centres.
    if (shift == 0.0) {
      ContactPatch whole;
      t.contact(env, {}, nullptr, whole);
      EXPECT_NEAR(totals(whole).bottom_area, 21 * 21 * s.cell * s.cell, 1e-12);
    }
  }
}

/// The 0.3 m plate of the next tests, [-0.155, 0.145] on both axes, its bottom at `bottom`.
RectangleProbe plate_at(double bottom) { return RectangleProbe(-0.155, -0.155, 0.145, 0.145, bottom); }

/// Presses the plate `depth` into the soil in one step.
void press_plate(Terrain& t, double depth) {
  const shore::EnvelopeRaster env = plate_at(-depth).envelope(t);
  const Imprint im{&env};
  t.step({&im, 1});
}

TEST(Contact, ARelievedColumnSpringsBackByWongsUnloadingLaw) {
  // Press a 0.3 m plate 3 cm into sand with A_u = 5e8 Pa/m^2, then lift it by g: each
  // column under it pushes with p_yield(z) - k_u g, k_u = A_u z (Wong's unloading line),
  // and not at all once g exceeds p_yield / k_u.
  TerrainSettings s;
  s.material.alpha = 0.0;
  s.material.unload_modulus = 5e8;
  Terrain t(s);
  const double z = 0.03, b = 0.3;
  press_plate(t, z);
  ASSERT_NEAR(t.sinkage(0, 0), z, 1e-12);
  const double p_yield = bekker::pressure(s.material, b, z), k_u = s.material.unload_modulus * z;
  const double reach = p_yield / k_u;  // 2.1 mm
  for (const double share : {0.0, 0.25, 0.8, 1.2}) {
    const double g = share * reach;
    const RectangleProbe lifted = plate_at(-z + g);
    ContactPatch patch;
    t.contact(lifted.envelope(t), {}, &lifted, patch);
    const ContactElement* centre = nullptr;
    for (const ContactElement& e : patch.elements)
      if (!e.wall && e.i == 0 && e.j == 0) centre = &e;
    if (share > 1.0) {
      EXPECT_EQ(centre, nullptr) << "a column " << g << " m below the plate still touches";
      continue;
    }
    ASSERT_NE(centre, nullptr) << share;
    EXPECT_NEAR(centre->stiffness, k_u, 1e-9 * k_u);
    EXPECT_NEAR(centre->pressure, p_yield, 1e-9 * p_yield) << share;
    EXPECT_NEAR(centre->preload, p_yield - k_u * g, 1e-9 * p_yield) << share;
  }
  // Pressed further (below the column tops) the columns load plastically: rigid up to yield.
  const RectangleProbe deeper = plate_at(-z - 0.005);
  ContactPatch patch;
  t.contact(deeper.envelope(t), {}, &deeper, patch);
  for (const ContactElement& e : patch.elements) {
    if (!e.wall && e.i == 0 && e.j == 0) {
      EXPECT_EQ(e.stiffness, kInf);
    }
  }
}

TEST(Contact, TheWallsOfAPlatesHoleResistAsBekkersCompactionResistance) {
  // Press a 0.3 m plate 4 cm into sand, then ask what the soil can do against it.
  TerrainSettings s;
  s.material.alpha = 0.0;  // no rim: the walls are the undisturbed ground
  Terrain t(s);
  const double z = 0.04, b = 0.3;
  press_plate(t, z);
  const RectangleProbe plate = plate_at(-z);
  const shore::EnvelopeRaster env = plate.envelope(t);
  ContactPatch patch;
  t.contact(env, {}, &plate, patch);
  const Totals sum = totals(patch);
  // Per unit length of wall: k z^(n+1) / (n + 1), k = k_c / b + k_phi.
  const Material& m = s.material;
  const double k = m.bekker_kc / b + m.bekker_kphi;
  const double per_side = b * k * std::pow(z, m.bekker_n + 1.0) / (m.bekker_n + 1.0);
  for (int side = 0; side < 4; ++side) EXPECT_NEAR(sum.wall_force[side], per_side, 0.05 * per_side) << side;
  EXPECT_EQ(patch.touching_columns, 30 * 30);
}

TEST(Contact, TheNormalFollowsTheUndersideOfACylinder) {
  // A wheel of radius 0.4 m, axis along y, its bottom 3 cm into fresh sand.
  TerrainSettings s;
  Terrain t(s);
  const double r = 0.4, cz = r - 0.03;
  shore::EnvelopeRaster env;
  env.resize(-45, -10, 91, 21, false);
  for (int y = 0; y < env.ny; ++y)
    for (int x = 0; x < env.nx; ++x) {
      const double dx = t.column_x(env.i0 + x);
      if (std::abs(dx) < r) env.lower[static_cast<std::size_t>(y) * env.nx + x] = cz - std::sqrt(r * r - dx * dx);
    }
  ContactPatch patch;
  t.contact(env, {}, nullptr, patch);
  ASSERT_GT(patch.touching_columns, 0);
  int checked = 0;
  for (const ContactElement& e : patch.elements) {
    if (e.wall || e.j != 0) continue;
    const double dx = e.point.x;
    // The underside's outward normal is (-dx, 0, sqrt(r^2 - dx^2)) / r; the soil pushes along it.
    EXPECT_NEAR(e.normal.x, -dx / r, 2e-3) << "at x " << dx;
    EXPECT_NEAR(e.normal.z, std::sqrt(r * r - dx * dx) / r, 2e-3);
    ++checked;
  }
  EXPECT_GT(checked, 10);  // the contact reaches about +-15 cm from the bottom
}

TEST(Contact, ShearDisplacementRemouldsTheSoil) {
  TerrainSettings s;
  Terrain t(s);
  const RectangleProbe plate(-0.1, -0.1, 0.1, 0.1, -0.02);
  const shore::EnvelopeRaster env = plate.envelope(t);
  std::vector<double> j(env.lower.size(), 0.05);
  ContactPatch fresh, sheared;
  t.contact(env, {}, nullptr, fresh);
  t.contact(env, j, nullptr, sheared);
  const double ratio = totals(sheared).bottom_force / totals(fresh).bottom_force;
  const Material& m = s.material;
  // Loosened soil bears at z what intact soil bears at s z: the pressure times s^n.
  const double s_loose = 1.0 - m.remould_ratio * (1.0 - std::exp(-0.05 / m.remould_length));
  EXPECT_NEAR(ratio, std::pow(s_loose, m.bekker_n), 1e-12);
  std::vector<double> wrong(3, 0.0);
  EXPECT_THROW(t.contact(env, wrong, nullptr, sheared), shore::InvalidSetting);
}

TEST(Contact, BedrockCarriesAnything) {
  TerrainSettings s;
  s.material.soil_depth = 0.05;
  Terrain t(s);
  const RectangleProbe plate(-0.05, -0.05, 0.05, 0.05, -0.06);
  ContactPatch patch;
  t.contact(plate.envelope(t), {}, nullptr, patch);
  ASSERT_FALSE(patch.elements.empty());
  for (const ContactElement& e : patch.elements) EXPECT_EQ(e.pressure, kInf);
}

TEST(Shear, JanosiHanamotoAndRemoulding) {
  const Material m = Material::sand();
  const double sigma = 30e3, j = 0.012;
  const double tau = (m.cohesion + sigma * std::tan(m.friction_angle)) * (1.0 - std::exp(-j / m.shear_modulus));
  EXPECT_NEAR(shear::stress(m, sigma, j), tau, 1e-9 * tau);
  EXPECT_NEAR(shear::stress(m, sigma, -j), tau, 1e-9 * tau);  // the law reads |j|
  EXPECT_EQ(shear::stress(m, sigma, 0.0), 0.0);
  EXPECT_NEAR(shear::strength(m, sigma), m.cohesion + sigma * std::tan(28.0 * std::numbers::pi / 180.0), 1e-9);
  EXPECT_EQ(shear::remoulding(m, 0.0), 1.0);
  EXPECT_NEAR(shear::loosening(m, 10.0), 1.0 - m.remould_ratio, 1e-12);
  // Loosened soil bears as intact soil pressed (1 - remould_ratio) as deep: Bekker's
  // pressure times that to the power n.
  EXPECT_NEAR(shear::remoulding(m, 10.0), std::pow(1.0 - m.remould_ratio, m.bekker_n), 1e-12);
  EXPECT_NEAR(shear::strength_remoulding(m, 10.0), 1.0 - m.remould_shear_ratio, 1e-12);
}

TEST(Shear, MaterialsRejectBadShearParametersByName) {
  auto expect_bad = [](auto edit, const std::string& field) {
    Material m = Material::sand();
    edit(m);
    try {
      m.validate();
      FAIL() << field << " accepted";
    } catch (const shore::InvalidSetting& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  expect_bad([](Material& m) { m.cohesion = -1.0; }, "cohesion");
  expect_bad([](Material& m) { m.friction_angle = std::numbers::pi / 2; }, "friction_angle");
  expect_bad([](Material& m) { m.friction_angle = std::nan(""); }, "friction_angle");
  expect_bad([](Material& m) { m.shear_modulus = 0.0; }, "shear_modulus");
  expect_bad([](Material& m) { m.remould_ratio = 1.0; }, "remould_ratio");
  expect_bad([](Material& m) { m.remould_shear_ratio = -0.1; }, "remould_shear_ratio");
  expect_bad([](Material& m) { m.remould_length = -0.01; }, "remould_length");
  expect_bad([](Material& m) { m.unload_modulus = -1.0; }, "unload_modulus");
  expect_bad([](Material& m) { m.unload_modulus = kInf; }, "unload_modulus");
  for (const char* name : {"sand", "mud", "snow", "rigid"}) EXPECT_NO_THROW(Material::preset(name).validate());
}

TEST(Sinkage, LooseSoilLaidOnTopBearsNothing) {
  // All displaced soil goes to the ring around a pressed plate: those columns rise by their
  // deposit and record it as negative sinkage, so pressing them back to the original level
  // finds fresh soil (no bearing), as if nothing had been laid there.
  TerrainSettings s;
  s.material.alpha = 1.0;
  s.max_erosion_passes = 0;
  Terrain t(s);
  const shore::EnvelopeRaster env = shore::terrain::testing::box_envelope(-5, -5, 10, 10, -0.01);
  const Imprint im{&env};
  t.step({&im, 1});
  const double rise = t.height(5, 0) - t.base_height(5, 0);
  ASSERT_GT(rise, 1e-4);
  EXPECT_DOUBLE_EQ(t.sinkage(5, 0), -rise);
  // A plate pressed exactly to the original ground over the ring column carries nothing there.
  const shore::EnvelopeRaster ring = shore::terrain::testing::box_envelope(5, 0, 1, 1, t.base_height(5, 0));
  const Bearing bearing = t.bearing(ring);
  ASSERT_EQ(bearing.contact_columns, 1);
  EXPECT_EQ(bearing.capacity, 0.0);
}

TEST(Sinkage, ShearParametersSurviveSaveAndLoad) {
  TerrainSettings s;
  s.material.cohesion = 123.0;
  s.material.friction_angle = 0.3;
  s.material.shear_modulus = 0.02;
  s.material.remould_ratio = 0.4;
  s.material.remould_shear_ratio = 0.1;
  s.material.remould_length = 0.07;
  s.material.unload_modulus = 4e8;
  const Terrain t(s);
  const auto file = std::filesystem::temp_directory_path() / "shore_shear_params.state";
  t.save(file);
  const Terrain u = Terrain::load(file);
  const Material& m = u.settings().material;
  EXPECT_EQ(m.cohesion, 123.0);
  EXPECT_EQ(m.friction_angle, 0.3);
  EXPECT_EQ(m.shear_modulus, 0.02);
  EXPECT_EQ(m.remould_ratio, 0.4);
  EXPECT_EQ(m.remould_shear_ratio, 0.1);
  EXPECT_EQ(m.remould_length, 0.07);
  EXPECT_EQ(m.unload_modulus, 4e8);
  std::filesystem::remove(file);
}

}  // namespace
