// Layers in depth: a plate on a crust sinks by the crust's Bekker law while its sinkage
// stays within the crust, and by the two-piece law (the crust's pressure at its boundary
// plus the lower soil's law beyond it) once it breaks through, which the test solves
// independently; broken-through columns show their lower material; bad layers are refused
// with the terrain untouched; layers are state (hash, file) and cost nothing unpainted.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include "shore/core/error.h"
#include "shore/terrain/bekker.h"
#include "shore/terrain/soil_delta.h"
#include "shore/terrain/terrain.h"
#include "terrain_fixtures.h"

using namespace shore::terrain;
using namespace shore::terrain::testing;

namespace {

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

/// Bekker's rolling wheel on the two-piece law: the sinkage z0 at which the front arc,
/// pressing fresh soil to z(x) = z0 - (r - sqrt(r^2 - x^2)), carries W = b * integral of
/// p(z(x)) dx (midpoint rule, 4000 strips; bisection on z0).
double rolling_two_piece(const Material& upper, const Material& lower, double d, double W, double D, double b) {
  const double r = D / 2;
  const auto carried = [&](double z0) {
    const double reach = std::sqrt(2 * r * z0 - z0 * z0);
    constexpr int kStrips = 4000;
    double sum = 0.0;
    for (int k = 0; k < kStrips; ++k) {
      const double x = (k + 0.5) * reach / kStrips;
      sum += two_piece(upper, lower, d, b, z0 - (r - std::sqrt(r * r - x * x)));
    }
    return b * sum * reach / kStrips;
  };
  double lo = 0.0, hi = 0.5 * r;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (carried(mid) < W ? lo : hi) = mid;
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
  // Unlayered again, the file (a map's, version 8, its layers block empty) loads without layers.
  t.clear_layers({-100, -100, 200, 200});
  const std::vector<unsigned char> unlayered = t.save_bytes();
  EXPECT_EQ(unlayered[8], 8);
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

TEST(Layers, DeltasCarryTheLayersToAReplica) {
  // A server that paints a crust, presses through it, re-layers part and clears part; a
  // replica driven only by exact deltas ends with its layers and its state hash.
  const Material crust = packed_sand(), sand = Material::sand();
  Terrain server(one_thread(sand)), replica(one_thread(sand));
  std::uint64_t sent = server.generation(), mirrored = sent;
  std::vector<std::uint32_t> versions;
  const auto sync = [&] {
    DeltaSettings exact;
    exact.quantum = 0.0;
    const std::vector<unsigned char> delta = SoilDelta::encode(server, sent, exact);
    std::uint32_t v = 0;
    std::memcpy(&v, delta.data() + 8, sizeof v);
    versions.push_back(v);
    sent = server.generation();
    mirrored = SoilDelta::apply(replica, delta, mirrored);
  };
  server.set_palette({sand, crust});
  server.paint_rect({-40, -40, 80, 80}, 1);
  sync();  // a map without layers: version 3
  server.paint_layer_rect({-40, -40, 80, 80}, 0, 0.005);
  (void)ramp_plate(server, -15, -15, 30e3);
  sync();
  server.paint_layer_disc(0.2, 0.2, 0.1, 0, 0.01);
  server.clear_layers({-40, -40, 20, 80});
  sync();
  EXPECT_EQ(versions, (std::vector<std::uint32_t>{3, 5, 5}));
  EXPECT_EQ(replica.state_hash(), server.state_hash());
  for (std::int64_t j = -40; j < 40; j += 3)
    for (std::int64_t i = -40; i < 40; i += 3) {
      ASSERT_EQ(replica.lower_index(i, j), server.lower_index(i, j)) << i << ", " << j;
      ASSERT_EQ(replica.layer_boundary(i, j), server.layer_boundary(i, j)) << i << ", " << j;
    }
  // The replica bears as the server does (the two-piece law on its broken crust).
  const shore::EnvelopeRaster env = box_envelope(-10, -10, 20, 20, server.height(0, 0));
  EXPECT_EQ(replica.bearing_offset(env, 2000.0), server.bearing_offset(env, 2000.0));
}

TEST(Layers, AStepStampsRepaintedOnlyTheTilesWhoseMapOrLayersChanged) {
  // The bench's map (four copies of sand in half-metre stripes, the two rows' border under
  // the wheel's middle) under its towed wheel: soil slumping across the border lays crusts
  // and erosion tracks the rut's layers every step. A tile a step names as repainted
  // (painted_since, what deltas, renderers and the heightfield's friction follow) holds a
  // column whose index or layers changed in that step, and no other tile changed.
  TerrainSettings s = one_thread(Material::sand());
  s.cell = 0.01;
  s.tile_columns = 8;  // small tiles: some hold only columns whose layering came back
  Terrain t(s);
  std::vector<Material> palette(4, Material::sand());
  for (int k = 1; k < 4; ++k) palette[static_cast<std::size_t>(k)].name = "sand " + std::to_string(k);
  t.set_palette(palette);
  for (int k = 0; k < 8; ++k) {
    t.paint_rect({k * 50, -20, 50, 20}, k % 4);
    t.paint_rect({k * 50, 0, 50, 20}, (k + 1) % 4);
  }
  // Every column's index, lower index and boundary over the tiles the wheel reaches.
  const shore::GridRect area{-64, -64, 256, 128};
  const auto column = [&](std::int64_t i, std::int64_t j) {
    return std::tuple{t.material_index(i, j), t.lower_index(i, j), t.layer_boundary(i, j)};
  };
  using Column = decltype(column(0, 0));
  std::vector<Column> seen;
  for (std::int64_t j = area.j0; j < area.j0 + area.ny; ++j)
    for (std::int64_t i = area.i0; i < area.i0 + area.nx; ++i) seen.push_back(column(i, j));
  const auto at = [&](std::int64_t i, std::int64_t j) -> Column& {
    return seen[static_cast<std::size_t>((j - area.j0) * area.nx + (i - area.i0))];
  };
  int stamped = 0, layered_steps = 0;
  for (int k = 0; k < 150; ++k) {  // the axle from 0 to 0.62 m: across a stripe's border
    const double x = k / 240.0;
    const double d = t.bearing_offset(wheel(t, x, 0.0, 0.8, 0.2), 4000.0);
    const shore::EnvelopeRaster env = wheel(t, x, -d, 0.8, 0.2);
    const Imprint im{&env};
    const std::uint64_t before = t.generation();
    t.step({&im, 1});
    for (const shore::GridRect& tile : t.painted_since(before)) {
      ASSERT_GE(tile.i0, area.i0);
      ASSERT_LE(tile.i0 + tile.nx, area.i0 + area.nx);
      ASSERT_GE(tile.j0, area.j0);
      ASSERT_LE(tile.j0 + tile.ny, area.j0 + area.ny);
      int changed = 0;
      for (std::int64_t j = tile.j0; j < tile.j0 + tile.ny; ++j)
        for (std::int64_t i = tile.i0; i < tile.i0 + tile.nx; ++i) {
          const Column now = column(i, j);
          if (now != at(i, j)) ++changed;
          at(i, j) = now;
        }
      EXPECT_GT(changed, 0) << "step " << k << ", tile at " << tile.i0 << ", " << tile.j0;
      ++stamped;
    }
    layered_steps += t.lower_index(t.column_i(x), 0) >= 0 ? 1 : 0;
  }
  EXPECT_GT(stamped, 0);
  EXPECT_GT(layered_steps, 0);
  // What no step named as repainted is as it was.
  for (std::int64_t j = area.j0; j < area.j0 + area.ny; ++j)
    for (std::int64_t i = area.i0; i < area.i0 + area.nx; ++i) ASSERT_EQ(column(i, j), at(i, j)) << i << ", " << j;
}

TEST(Layers, ATowedWheelCrossingOntoACrustRidesOnItOrBreaksThrough) {
  // The bench's wheel (D 0.8 m, b 0.2 m, 4 kN) towed over sand, then from x = 1 m over a
  // packed crust on sand: 5 cm thick it carries the wheel as packed sand alone would; 1.5 cm
  // thick the wheel breaks through, to the two-piece law's rolling sinkage.
  const double W = 4000, D = 0.8, b = 0.2;
  const Material sand = Material::sand(), crust = packed_sand();
  const auto crusted = [&](double depth) {
    Terrain t(one_thread(sand));
    t.set_palette({sand, crust});
    t.paint_rect({100, -50, 400, 100}, 1);
    t.paint_layer_rect({100, -50, 400, 100}, 0, depth);
    return tow(t, W, D, b);
  };
  const std::vector<double> thick = crusted(0.05), thin = crusted(0.015);
  Terrain packed_alone(one_thread(crust));
  const std::vector<double> on_packed = tow(packed_alone, W, D, b);
  const double thick_z = mean_depth(thick, 1.75, 2.0), thin_z = mean_depth(thin, 1.75, 2.0);
  const double packed_z = mean_depth(on_packed, 1.75, 2.0), sand_z = mean_depth(thick, 0.35, 0.6);
  const double ref_thick = rolling_two_piece(crust, sand, 0.05, W, D, b);
  const double ref_thin = rolling_two_piece(crust, sand, 0.015, W, D, b);
  const double ref_sand = rolling_two_piece(sand, sand, 1.0, W, D, b);
  std::printf(
      "[ towed ] sand %.4f m (arc integral %.4f, Bekker rolling %.4f); 5 cm crust %.4f m (packed alone %.4f, arc "
      "integral %.4f); 1.5 cm crust %.4f m (two-piece arc integral %.4f)\n",
      sand_z, ref_sand, bekker::wheel_sinkage_rolling(sand, W, D, b), thick_z, packed_z, ref_thick, thin_z, ref_thin);
  ASSERT_LT(ref_thick, 0.05);
  EXPECT_NEAR(thick_z, packed_z, 0.01 * packed_z);  // within the crust: as on the crust alone
  ASSERT_GT(ref_thin, 0.015);
  EXPECT_GT(thin_z, 0.015);  // broken through
  EXPECT_GT(thin_z, 1.1 * packed_z);
  EXPECT_LT(thin_z, sand_z);
  // The quasi-static column wheel against the front arc's Bekker integral (as the one-soil
  // towed wheel against Bekker's rolling wheel).
  EXPECT_NEAR(sand_z, ref_sand, 0.1 * ref_sand);
  EXPECT_NEAR(thick_z, ref_thick, 0.1 * ref_thick);
  EXPECT_NEAR(thin_z, ref_thin, 0.1 * ref_thin);
  // The column wheel falls short of the arc integral by the same share on the broken crust
  // as on sand alone.
  EXPECT_NEAR(thin_z / ref_thin, sand_z / ref_sand, 0.03);
}

TEST(Layers, APressedColumnCompactsByTheCrustsAlphaThenTheLowerOnes) {
  // A box pressed 1 cm into fresh mud (alpha 0.41) layered over snow (alpha 0) 4 mm down:
  // each column compacts 4 mm by mud's share and 6 mm by snow's.
  const Material mud = Material::mud(), snow = Material::snow();
  Terrain t(one_thread(mud));
  t.set_palette({mud, snow});
  t.paint_layer_rect({-20, -20, 40, 40}, 1, 0.004);
  const shore::EnvelopeRaster env = box_envelope(-10, -10, 20, 20, -0.01);
  const Imprint im{&env};
  const StepReport r = t.step({&im, 1});
  const double area = 0.01 * 0.01;
  const double expected = 400 * area * (0.004 * (1.0 - mud.alpha) + 0.006 * (1.0 - snow.alpha));
  EXPECT_EQ(r.contact_columns, 400);
  EXPECT_NEAR(r.compacted_volume, expected, 1e-12 * expected);
  EXPECT_EQ(t.exposed_index(0, 0), 1);
}

TEST(Layers, ErosionGivesByTheExposedLayersSlopeLimits) {
  // A 60 degree cone on columns pressed 1 cm: a mud crust (repose 63 degrees) 5 cm thick
  // holds it; 5 mm thick it is broken through, and the sand beneath (repose 25 degrees)
  // slumps.
  const Material mud = Material::mud(), sand = Material::sand();
  const auto steepest_after_relax = [&](double crust) {
    TerrainSettings s = one_thread(mud);
    s.max_erosion_passes = 1000;
    Terrain t(s);
    t.set_palette({mud, sand});
    t.paint_layer_rect({-40, -40, 80, 80}, 1, crust);
    const shore::EnvelopeRaster env = box_envelope(-30, -30, 60, 60, -0.01);
    const Imprint im{&env};
    t.step({&im, 1});
    const double r = 0.10, slope = std::numbers::pi / 3;
    for (std::int64_t j = -12; j <= 12; ++j)
      for (std::int64_t i = -12; i <= 12; ++i) {
        const double d = std::hypot(t.column_x(i), t.column_y(j));
        if (d < r) t.set_height(i, j, -0.01 + (r - d) * std::tan(slope));
      }
    int rounds = 0;
    while (t.relax({-25, -25, 50, 50}).erosion_passes == s.max_erosion_passes && rounds < 200) ++rounds;
    double steepest = 0.0;
    for (std::int64_t j = -20; j < 20; ++j)
      for (std::int64_t i = -20; i < 20; ++i)
        for (int dj = -1; dj <= 1; ++dj)
          for (int di = -1; di <= 1; ++di) {
            if (!di && !dj) continue;
            const double drop = t.height(i, j) - t.height(i + di, j + dj);
            steepest = std::max(steepest, std::atan(drop / (0.01 * std::hypot(di, dj))));
          }
    return steepest;
  };
  const double one_degree = std::numbers::pi / 180;
  const double whole = steepest_after_relax(0.05), broken = steepest_after_relax(0.005);
  std::printf(
      "[ erosion ] steepest %.2f deg on a whole mud crust (repose %.2f), %.2f deg broken through to sand "
      "(repose %.2f)\n",
      whole / one_degree, mud.theta_out / one_degree, broken / one_degree, sand.theta_out / one_degree);
  EXPECT_GT(whole, std::numbers::pi / 3 - 5 * one_degree);
  EXPECT_LE(broken, sand.theta_out + one_degree);
}
