// Layers in depth: a plate on a crust sinks by the crust's Bekker law while its sinkage
// stays within the crust, and by the two-piece law (the crust's pressure at its boundary
// plus the lower soil's law beyond it) once it breaks through, which the test solves
// independently; broken-through columns show their lower material; bad layers are refused
// with the terrain untouched; layers are state (hash, file) and cost nothing unpainted.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "shore/core/error.h"
#include "shore/terrain/bekker.h"
#include "shore/terrain/terrain.h"
#include "terrain_fixtures.h"

using namespace shore::terrain;
using namespace shore::terrain::testing;

namespace {

constexpr int kPlate = 30;  // 0.3 m x 0.3 m at 1 cm
constexpr double kWidth = 0.3;

/// Sand four times as stiff as Wong's dry sand: a packed crust.
Material packed_sand() {
  Material m = Material::sand();
  m.name = "packed";
  m.bekker_kphi *= 4.0;
  return m;
}

/// Nearly rigid ice under snow (Bekker n 1, k_phi 1e9 Pa/m).
Material ice() {
  Material m = Material::snow();
  m.name = "ice";
  m.bekker_n = 1.0;
  m.bekker_kc = 0.0;
  m.bekker_kphi = 1e9;
  return m;
}

TerrainSettings one_thread(const Material& m) {
  TerrainSettings s;
  s.material = m;
  s.threads = 1;
  return s;
}

/// Ramps a plate whose lower-left column is (i0, j0) from 0 to pressure p over 20 steps,
/// each lowering it by the bearing offset for the load and pressing it in. Returns its depth.
double ramp_plate(Terrain& t, std::int64_t i0, std::int64_t j0, double p) {
  constexpr int kSteps = 20;
  double depth = 0.0;
  for (int k = 1; k <= kSteps; ++k) {
    const double load = p * kWidth * kWidth * k / kSteps;
    const shore::EnvelopeRaster here = box_envelope(i0, j0, kPlate, kPlate, -depth);
    depth += t.bearing_offset(here, load);
    const shore::EnvelopeRaster env = box_envelope(i0, j0, kPlate, kPlate, -depth);
    const Imprint im{&env};
    t.step({&im, 1});
  }
  return depth;
}

/// The two-piece Bekker law of a plate of width b on a crust of `upper`, d thick, over
/// `lower`: p(z) = P_u(z) for z <= d, P_u(d) + P_l(z - d) beyond (std::pow, not the
/// terrain's tables).
double two_piece(const Material& upper, const Material& lower, double d, double b, double z) {
  const auto piece = [b](const Material& m, double s) {
    return s <= 0.0 ? 0.0 : (m.bekker_kc / b + m.bekker_kphi) * std::pow(s, m.bekker_n);
  };
  return z <= d ? piece(upper, z) : piece(upper, d) + piece(lower, z - d);
}

/// The sinkage at which the two-piece law carries p, by bisection.
double two_piece_sinkage(const Material& upper, const Material& lower, double d, double b, double p) {
  double lo = 0.0, hi = 1.0;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (two_piece(upper, lower, d, b, mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

TEST(Layers, APlateWithinItsCrustSinksAsOnTheCrustAlone) {
  // A packed crust 5 cm thick over loose sand; 50 kPa presses packed sand 12.65 mm.
  const Material crust = packed_sand(), sand = Material::sand();
  Terrain layered(one_thread(sand));
  layered.set_palette({sand, crust});
  layered.paint_rect({-40, -40, 80, 80}, 1);
  layered.paint_layer_rect({-40, -40, 80, 80}, 0, 0.05);
  Terrain crust_only(one_thread(sand));
  crust_only.set_palette({sand, crust});
  crust_only.paint_rect({-40, -40, 80, 80}, 1);
  const double p = 50e3;
  const double on_crust = ramp_plate(layered, -15, -15, p);
  const double alone = ramp_plate(crust_only, -15, -15, p);
  const double ref = bekker::plate_sinkage(crust, kWidth, p);
  std::printf("[ crust ] 5 cm packed over sand at 50 kPa: %.7f m, packed alone %.7f m, Bekker %.7f m\n", on_crust,
              alone, ref);
  ASSERT_LT(on_crust, 0.05);
  EXPECT_EQ(on_crust, alone);  // the crust's piece is the one-layer law, bit for bit
  EXPECT_NEAR(on_crust, ref, 0.02 * ref);
  EXPECT_EQ(layered.exposed_index(0, 0), 1);  // not broken through
  EXPECT_EQ(layered.lower_index(0, 0), 0);
}

TEST(Layers, APlateBreakingThroughSinksByTheTwoPieceLaw) {
  struct Case {
    Material upper, lower;
    double depth, p;  // crust thickness m, plate pressure Pa
  };
  const std::vector<Case> cases = {
      {packed_sand(), Material::sand(), 0.005, 50e3},  // a thin packed crust over loose sand
      {Material::snow(), ice(), 0.03, 8e3},            // snow over ice
  };
  for (const Case& c : cases) {
    Terrain t(one_thread(c.upper));
    t.set_palette({c.upper, c.lower});
    t.paint_layer_rect({-40, -40, 80, 80}, 1, c.depth);
    const double depth = ramp_plate(t, -15, -15, c.p);
    const double ref = two_piece_sinkage(c.upper, c.lower, c.depth, kWidth, c.p);
    const double upper_alone = bekker::plate_sinkage(c.upper, kWidth, c.p);
    const double lower_alone = bekker::plate_sinkage(c.lower, kWidth, c.p);
    std::printf(
        "[ break ] %s %.3f m over %s at %.0f Pa: %.7f m, two-piece Bekker %.7f m (%s alone %.7f, %s alone %.7f)\n",
        c.upper.name.c_str(), c.depth, c.lower.name.c_str(), c.p, depth, ref, c.upper.name.c_str(), upper_alone,
        c.lower.name.c_str(), lower_alone);
    EXPECT_GT(depth, c.depth);
    EXPECT_NEAR(depth, ref, 0.02 * (ref - c.depth) + 1e-5) << c.upper.name;
    // Under the plate the crust is broken: the column shows its lower material.
    EXPECT_EQ(t.material_index(0, 0), 0);
    EXPECT_EQ(t.exposed_index(0, 0), 1);
    EXPECT_EQ(t.exposed_material(0, 0).name, c.lower.name);
    EXPECT_EQ(t.exposed_index(30, 30), 0);  // beside it the crust is whole
  }
}

TEST(Layers, ContactPushesWithTheTwoPieceLaw) {
  const Material crust = packed_sand(), sand = Material::sand();
  Terrain t(one_thread(sand));
  t.set_palette({sand, crust});
  t.paint_rect({-20, -20, 40, 40}, 1);
  t.paint_layer_rect({0, -20, 20, 40}, 0, 0.004);  // the right half is layered, 4 mm crust
  const double depth = 0.01;                       // into fresh soil: sinkage = depth
  const shore::EnvelopeRaster env = box_envelope(-10, -10, 20, 20, -depth);
  ContactPatch patch;
  t.contact(env, {}, nullptr, patch);
  int seen = 0;
  for (const ContactElement& el : patch.elements) {
    if (el.wall) continue;
    const bool layered = el.i >= 0;
    const double expected = layered ? two_piece(crust, sand, 0.004, patch.patch_width, depth)
                                    : bekker::pressure(crust, patch.patch_width, depth);
    EXPECT_NEAR(el.pressure, expected, 1e-12 * expected) << el.i << ", " << el.j;
    seen += layered ? 1 : 0;
  }
  EXPECT_EQ(seen, 200);
}

TEST(Layers, BadLayersAreRefusedAndChangeNothing) {
  Terrain t(one_thread(Material::sand()));
  t.set_palette({Material::sand(), Material::mud()});
  t.paint_layer_rect({0, 0, 10, 10}, 1, 0.02);
  const std::uint64_t before = t.state_hash();
  const auto invalid = [](const std::function<void()>& f) { return message_of<shore::InvalidSetting>(f); };
  std::string m = invalid([&] { t.paint_layer_rect({0, 0, 5, 5}, 2, 0.01); });
  EXPECT_NE(m.find("paint_layer_rect.lower_index = 2"), std::string::npos) << m;
  EXPECT_NE(m.find("[0, 1]"), std::string::npos) << m;
  m = invalid([&] { t.paint_layer_disc(0.0, 0.0, 0.1, -1, 0.01); });
  EXPECT_NE(m.find("paint_layer_disc.lower_index = -1"), std::string::npos) << m;
  m = invalid([&] { t.paint_layer_rect({0, 0, 5, 5}, 1, -0.01); });
  EXPECT_NE(m.find("paint_layer_rect.depth = -0.01"), std::string::npos) << m;
  m = invalid([&] { t.paint_layer_rect({0, 0, 5, 5}, 1, std::numeric_limits<double>::quiet_NaN()); });
  EXPECT_NE(m.find("paint_layer_rect.depth"), std::string::npos) << m;
  m = invalid([&] { t.paint_layer_disc(0.0, 0.0, 0.1, 1, std::numeric_limits<double>::infinity()); });
  EXPECT_NE(m.find("paint_layer_disc.depth"), std::string::npos) << m;
  m = invalid([&] {
    t.paint_layer_where(
        {0, 0, 5, 5}, [](double, double) { return true; }, 1, 2e6);
  });
  EXPECT_NE(m.find("paint_layer_where.depth = 2000000"), std::string::npos) << m;
  m = invalid([&] { t.paint_layer_rect({0, 0, -3, 5}, 1, 0.01); });
  EXPECT_NE(m.find("rect.nx = -3"), std::string::npos) << m;
  // A palette too short for a lower index on the map is refused.
  m = invalid([&] { t.set_palette({Material::sand()}); });
  EXPECT_NE(m.find("largest index painted on the map (1)"), std::string::npos) << m;
  EXPECT_EQ(t.state_hash(), before);
  EXPECT_EQ(t.lower_index(3, 3), 1);
  EXPECT_EQ(t.layer_boundary(3, 3), 0.02);
  EXPECT_EQ(t.lower_index(20, 3), -1);
}

TEST(Layers, LayersAreStateAndClearingThemRestoresTheHash) {
  Terrain t(one_thread(Material::sand()));
  t.set_palette({Material::sand(), Material::mud()});
  const std::uint64_t plain = t.state_hash();
  t.paint_layer_disc(0.05, 0.0, 0.1, 1, 0.02);
  EXPECT_NE(t.state_hash(), plain);
  EXPECT_EQ(t.lower_index(5, 0), 1);
  EXPECT_EQ(t.lower_index(30, 0), -1);
  t.clear_layers({-50, -50, 100, 100});
  EXPECT_EQ(t.state_hash(), plain);
  EXPECT_EQ(t.lower_index(5, 0), -1);
}

TEST(Layers, ASavedLayeredTerrainLoadsBitIdenticalAndStepsOnAlike) {
  const Material crust = packed_sand(), sand = Material::sand();
  Terrain t(one_thread(sand));
  t.set_palette({sand, crust});
  t.paint_rect({-40, -40, 80, 80}, 1);
  t.paint_layer_disc(0.0, 0.0, 0.25, 0, 0.005);
  (void)ramp_plate(t, -15, -15, 30e3);  // broken through under the plate
  const std::vector<unsigned char> bytes = t.save_bytes();
  Terrain back = Terrain::load_bytes(bytes, "layers");
  EXPECT_EQ(back.state_hash(), t.state_hash());
  EXPECT_EQ(back.save_bytes(), bytes);
  for (std::int64_t j = -30; j < 30; j += 7)
    for (std::int64_t i = -30; i < 30; i += 7) {
      ASSERT_EQ(back.lower_index(i, j), t.lower_index(i, j)) << i << ", " << j;
      ASSERT_EQ(back.layer_boundary(i, j), t.layer_boundary(i, j)) << i << ", " << j;
      ASSERT_EQ(back.exposed_index(i, j), t.exposed_index(i, j)) << i << ", " << j;
    }
  // Both press on alike.
  EXPECT_EQ(ramp_plate(back, -5, -5, 40e3), ramp_plate(t, -5, -5, 40e3));
  EXPECT_EQ(back.state_hash(), t.state_hash());
  // Unlayered again, the file is the map's version 6, and loads without layers.
  t.clear_layers({-100, -100, 200, 200});
  const std::vector<unsigned char> unlayered = t.save_bytes();
  EXPECT_EQ(unlayered[8], 6);
  EXPECT_EQ(Terrain::load_bytes(unlayered, "unlayered").lower_index(0, 0), -1);
}

TEST(Layers, AnUnlayeredColumnOfALayeredTerrainComputesAsWithoutLayers) {
  // Layers far from where the sphere rolls: every column it touches takes the first piece,
  // which is the one-layer law bit for bit, and the other stages' paths agree too.
  Terrain plain(one_thread(Material::sand()));
  plain.set_palette({Material::sand(), Material::mud()});
  Terrain layered(one_thread(Material::sand()));
  layered.set_palette({Material::sand(), Material::mud()});
  layered.paint_layer_rect({200, 200, 10, 10}, 1, 0.01);
  for (Terrain* t : {&plain, &layered})
    for (int k = 0; k < 30; ++k) {
      const shore::EnvelopeRaster env = sphere_envelope(*t, 0.002 * k, 0.0, 0.06 - 0.0005 * k, 0.08);
      const Imprint im{&env};
      t->step({&im, 1});
    }
  for (std::int64_t j = -30; j < 30; ++j)
    for (std::int64_t i = -30; i < 30; ++i) {
      ASSERT_EQ(layered.height(i, j), plain.height(i, j)) << i << ", " << j;
      ASSERT_EQ(layered.sinkage(i, j), plain.sinkage(i, j)) << i << ", " << j;
    }
  const shore::EnvelopeRaster env = sphere_envelope(plain, 0.03, 0.0, 0.05, 0.08);
  EXPECT_EQ(layered.bearing_offset(env, 40.0), plain.bearing_offset(env, 40.0));
}
