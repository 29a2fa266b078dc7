// One terrain, several soils: plates on a painted map sink as Bekker's law of the material
// under them, a plate across a border as both halves together, each column displaces and
// erodes by its own material, volume is conserved across borders, bad paint is refused,
// and a painted terrain saves and loads whole.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "shore/core/error.h"
#include "shore/core/hash.h"
#include "shore/terrain/bekker.h"
#include "shore/terrain/terrain.h"
#include "terrain_fixtures.h"

using namespace shore::terrain;
using namespace shore::terrain::testing;

namespace {

constexpr double kWidth = 0.3;

/// Sand four times as stiff as Wong's dry sand (a packed track).
Material packed_sand() {
  Material m = Material::sand();
  m.name = "packed";
  m.bekker_kphi *= 4.0;
  return m;
}

TerrainSettings one_thread(const Material& m) {
  TerrainSettings s;
  s.material = m;
  s.threads = 1;
  return s;
}

/// Sinkage z of a plate half on a, half on b under pressure p (Bekker on each half):
/// p = (p_a(z) + p_b(z)) / 2, by bisection.
double straddling_sinkage(const Material& a, const Material& b, double p) {
  double lo = 0.0, hi = 1.0;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    const double carried = 0.5 * (bekker::pressure(a, kWidth, mid) + bekker::pressure(b, kWidth, mid));
    (carried < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Steepest drop (rad) from a column to any 8-neighbour, over columns whose own material
// index is `index`, in the square [lo, hi)^2.
double steepest_from(const Terrain& t, int index, std::int64_t lo, std::int64_t hi) {
  double steepest = 0.0;
  const double cell = t.settings().cell;
  for (std::int64_t j = lo; j < hi; ++j)
    for (std::int64_t i = lo; i < hi; ++i) {
      if (t.material_index(i, j) != index) continue;
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          if (!di && !dj) continue;
          const double drop = t.height(i, j) - t.height(i + di, j + dj);
          steepest = std::max(steepest, std::atan(drop / (cell * std::hypot(di, dj))));
        }
    }
  return steepest;
}

}  // namespace

TEST(MaterialMap, NewTerrainHasOneMaterialEverywhere) {
  Terrain t(one_thread(Material::mud()));
  ASSERT_EQ(t.palette().size(), 1u);
  EXPECT_EQ(t.palette()[0].name, "mud");
  EXPECT_EQ(t.material_index(-1000, 77), 0);
  EXPECT_EQ(t.material_at(5, 5).name, "mud");
  EXPECT_EQ(t.tile_count(), 0u);
}

TEST(MaterialMap, PlatesOnFourMaterialsSinkAsBekkerOnEach) {
  struct Soil {
    Material m;
    double p;             // Pa
    std::int64_t i0, j0;  // plate corner, in the middle of its quadrant
  };
  const std::vector<Soil> soils = {{Material::sand(), 50e3, -65, -65},
                                   {Material::mud(), 20e3, 35, -65},
                                   {Material::snow(), 8e3, -65, 35},
                                   {packed_sand(), 50e3, 35, 35}};
  Terrain map(one_thread(Material::sand()));
  map.set_palette({soils[0].m, soils[1].m, soils[2].m, soils[3].m});
  map.paint_rect({0, -100, 100, 100}, 1);
  map.paint_where(
      {-100, -100, 200, 200}, [](double x, double y) { return x < 0.0 && y >= 0.0; }, 2);
  map.paint_rect({0, 0, 100, 100}, 3);
  for (std::size_t k = 0; k < soils.size(); ++k) {
    const Soil& s = soils[k];
    EXPECT_EQ(map.material_index(s.i0 + 15, s.j0 + 15), static_cast<int>(k));
    const double on_map = ramp_plate(map, s.i0, s.j0, s.p);
    Terrain alone(one_thread(s.m));
    const double by_itself = ramp_plate(alone, s.i0, s.j0, s.p);
    const double ref = bekker::plate_sinkage(s.m, kWidth, s.p);
    EXPECT_NEAR(on_map, ref, 0.02 * ref) << s.m.name;              // the column model's Bekker tolerance
    EXPECT_NEAR(on_map, by_itself, 0.01 * by_itself) << s.m.name;  // as on that soil alone
    std::printf("[ plate ] %-6s at %5.0f Pa: map %.7f m, alone %.7f m, Bekker %.7f m\n", s.m.name.c_str(), s.p, on_map,
                by_itself, ref);
  }
}

TEST(MaterialMap, PlateAcrossABorderSinksAsBothHalvesTogether) {
  const Material sand = Material::sand(), mud = Material::mud();
  const double p = 30e3;
  Terrain t(one_thread(sand));
  t.set_palette({sand, mud});
  t.paint_rect({0, -50, 50, 100}, 1);  // mud for i >= 0: the plate's right half
  const double depth = ramp_plate(t, -15, -15, p);
  const double on_sand = bekker::plate_sinkage(sand, kWidth, p), on_mud = bekker::plate_sinkage(mud, kWidth, p);
  const double both = straddling_sinkage(sand, mud, p);
  std::printf("[ straddle ] sand %.7f m, mud %.7f m, both halves (Bekker) %.7f m, map %.7f m\n", on_sand, on_mud, both,
              depth);
  EXPECT_GT(depth, std::min(on_sand, on_mud));
  EXPECT_LT(depth, std::max(on_sand, on_mud));
  EXPECT_NEAR(depth, both, 0.02 * both);
}

TEST(MaterialMap, ContactPushesWithTheColumnsOwnBekkerPressure) {
  const Material sand = Material::sand(), mud = Material::mud();
  Terrain t(one_thread(sand));
  t.set_palette({sand, mud});
  t.paint_rect({0, -20, 20, 40}, 1);
  const double depth = 0.01;  // into fresh soil: sinkage = depth
  const shore::EnvelopeRaster env = box_envelope(-10, -10, 20, 20, -depth);
  ContactPatch patch;
  t.contact(env, {}, nullptr, patch);
  int seen[2] = {0, 0};
  for (const ContactElement& el : patch.elements) {
    if (el.wall) continue;
    const Material& m = t.material_at(el.i, el.j);
    const double expected = bekker::pressure(m, patch.patch_width, depth);
    EXPECT_NEAR(el.pressure, expected, 1e-12 * expected) << el.i << ", " << el.j;
    ++seen[t.material_index(el.i, el.j)];
  }
  EXPECT_EQ(seen[0], 200);
  EXPECT_EQ(seen[1], 200);
}

TEST(MaterialMap, EachPressedColumnCompactsByItsOwnAlpha) {
  const Material sand = Material::sand(), mud = Material::mud();
  ASSERT_NE(sand.alpha, mud.alpha);
  Terrain t(one_thread(sand));
  t.set_palette({sand, mud});
  t.paint_rect({0, -20, 20, 40}, 1);
  const double depth = 0.01;
  const shore::EnvelopeRaster env = box_envelope(-10, -10, 20, 20, -depth);  // 200 columns of each
  const Imprint im{&env};
  const StepReport r = t.step({&im, 1});
  const double column = depth * 0.01 * 0.01;  // m^3 each column is pushed down
  const double expected = 200 * column * (1.0 - sand.alpha) + 200 * column * (1.0 - mud.alpha);
  EXPECT_EQ(r.contact_columns, 400);
  EXPECT_NEAR(r.displaced_volume, 400 * column, 1e-12);
  EXPECT_NEAR(r.compacted_volume, expected, 1e-9 * expected);
}

TEST(MaterialMap, ErosionAcrossABorderKeepsEachSidesAngleAndTheVolume) {
  // A 60 degree cone on the border: its mud half (repose 63 degrees) stands, its sand half
  // (repose 25 degrees) slumps, partly onto the mud.
  const Material sand = Material::sand(), mud = Material::mud();
  TerrainSettings s = one_thread(sand);
  s.max_erosion_passes = 1000;
  Terrain t(s);
  t.set_palette({sand, mud});
  t.paint_rect({-40, -40, 40, 80}, 1);  // mud for i < 0
  const double r = 0.10, slope = std::numbers::pi / 3;
  for (std::int64_t j = -12; j <= 12; ++j)
    for (std::int64_t i = -12; i <= 12; ++i) {
      const double d = std::hypot(t.column_x(i), t.column_y(j));
      if (d < r) t.set_height(i, j, (r - d) * std::tan(slope));
    }
  const double before = t.volume().ground;
  int rounds = 0;
  while (t.relax({-40, -40, 80, 80}).erosion_passes == s.max_erosion_passes && rounds < 200) ++rounds;
  ASSERT_LT(rounds, 200);
  const double one_degree = std::numbers::pi / 180;
  const double sand_side = steepest_from(t, 0, -39, 39), mud_side = steepest_from(t, 1, -39, 39);
  std::printf(
      "[ border ] steepest from sand %.2f deg (repose %.2f), from mud %.2f deg (repose %.2f); volume %.17g -> "
      "%.17g m^3\n",
      sand_side / one_degree, sand.theta_out / one_degree, mud_side / one_degree, mud.theta_out / one_degree, before,
      t.volume().ground);
  EXPECT_LE(sand_side, sand.theta_out + one_degree);
  EXPECT_GT(mud_side, slope - 5 * one_degree);  // mud holds the cone's 60 degrees
  // Each transfer is rounded where it lands (heights are doubles updated in place), so the
  // sum holds to rounding, as on one material: a few ulps of the 1.8e-3 m^3 moved.
  EXPECT_NEAR(t.volume().ground, before, 1e-15);
  EXPECT_NEAR(t.volume().ground, t.volume().edited, 1e-15);
}

TEST(MaterialMap, AnUnpaintedPaletteComputesWhatOneMaterialDoes) {
  // The per-column path with every column at entry 0 gives the one-material path's state.
  Terrain plain(one_thread(Material::sand()));
  Terrain mapped(one_thread(Material::sand()));
  mapped.set_palette({Material::sand(), Material::mud()});
  Material copy = Material::sand();
  copy.name = "copy";
  Terrain repainted(one_thread(Material::sand()));
  repainted.set_palette({Material::mud(), copy});
  repainted.paint_rect({-30, -30, 60, 60}, 1);  // sand's values everywhere the sphere goes
  for (Terrain* t : {&plain, &mapped, &repainted})
    for (int k = 0; k < 30; ++k) {
      const shore::EnvelopeRaster env = sphere_envelope(*t, 0.002 * k, 0.0, 0.06 - 0.0005 * k, 0.08);
      const Imprint im{&env};
      t->step({&im, 1});
    }
  EXPECT_EQ(mapped.state_hash(), plain.state_hash());
  for (std::int64_t j = -30; j < 30; ++j)
    for (std::int64_t i = -30; i < 30; ++i) {
      ASSERT_EQ(repainted.height(i, j), plain.height(i, j)) << i << ", " << j;
      ASSERT_EQ(repainted.sinkage(i, j), plain.sinkage(i, j)) << i << ", " << j;
    }
  EXPECT_NE(repainted.state_hash(), plain.state_hash());  // the painted map is state
}

TEST(MaterialMap, DiscsAndPredicatesPaintTheColumnsTheyCover) {
  Terrain t(one_thread(Material::sand()));
  t.set_palette({Material::sand(), Material::mud(), Material::snow()});
  const double cx = 0.123, cy = -0.047, radius = 0.1;
  t.paint_disc(cx, cy, radius, 1);
  t.paint_where(
      {-20, -20, 40, 40}, [](double x, double y) { return x + y > 0.1; }, 2);
  for (std::int64_t j = -30; j < 30; ++j)
    for (std::int64_t i = -10; i < 40; ++i) {
      const double x = t.column_x(i), y = t.column_y(j);
      int expected = std::hypot(x - cx, y - cy) <= radius ? 1 : 0;
      if (i >= -20 && i < 20 && j >= -20 && j < 20 && x + y > 0.1) expected = 2;
      ASSERT_EQ(t.material_index(i, j), expected) << i << ", " << j;
    }
  // Painting index 0 back everywhere restores the default map: the hash of unpainted soil.
  const std::uint64_t painted = t.state_hash();
  t.paint_rect({-50, -50, 100, 100}, 0);
  EXPECT_NE(t.state_hash(), painted);
  EXPECT_EQ(t.state_hash(), Terrain(one_thread(Material::sand())).state_hash());
}

TEST(MaterialMap, BadPaintAndPalettesAreRefusedAndChangeNothing) {
  Terrain t(one_thread(Material::sand()));
  t.set_palette({Material::sand(), Material::mud()});
  t.paint_rect({0, 0, 10, 10}, 1);
  const std::uint64_t before = t.state_hash();
  const auto invalid = [](const std::function<void()>& f) { return message_of<shore::InvalidSetting>(f); };
  std::string m = invalid([&] { t.paint_rect({0, 0, 5, 5}, 2); });
  EXPECT_NE(m.find("paint_rect.index = 2"), std::string::npos) << m;
  EXPECT_NE(m.find("[0, 1]"), std::string::npos) << m;
  m = invalid([&] { t.paint_disc(0.0, 0.0, 0.1, -1); });
  EXPECT_NE(m.find("paint_disc.index = -1"), std::string::npos) << m;
  m = invalid([&] { t.paint_disc(0.0, 0.0, -0.1, 1); });
  EXPECT_NE(m.find("radius"), std::string::npos) << m;
  m = invalid([&] { t.paint_disc(0.0, 0.0, 1e12, 1); });  // 2e14 columns a side
  EXPECT_NE(m.find("radius = 1000000000000: must cover at most 67108864 columns"), std::string::npos) << m;
  m = invalid([&] {
    t.paint_where(
        {0, 0, 5, 5}, [](double, double) { return true; }, 300);
  });
  EXPECT_NE(m.find("paint_where.index = 300"), std::string::npos) << m;
  m = invalid([&] { t.paint_rect({0, 0, -3, 5}, 1); });
  EXPECT_NE(m.find("rect.nx = -3"), std::string::npos) << m;
  // A predicate that throws paints nothing.
  EXPECT_THROW(t.paint_where(
                   {-5, -5, 20, 20},
                   [](double x, double) {
                     if (x > 0.05) throw std::runtime_error("predicate failed");
                     return true;
                   },
                   0),
               std::runtime_error);
  // Palettes.
  m = invalid([&] { t.set_palette({}); });
  EXPECT_NE(m.find("set_palette.size() = 0"), std::string::npos) << m;
  m = invalid([&] { t.set_palette(std::vector<Material>(257, Material::sand())); });
  EXPECT_NE(m.find("set_palette.size() = 257"), std::string::npos) << m;
  Material bad = Material::mud();
  bad.bekker_n = 5.0;
  m = invalid([&] { t.set_palette({Material::sand(), bad}); });
  EXPECT_NE(m.find("set_palette[1]"), std::string::npos) << m;
  EXPECT_NE(m.find("bekker_n = 5"), std::string::npos) << m;
  Material deep = Material::mud();
  deep.soil_depth = 2.0;
  m = invalid([&] { t.set_palette({Material::sand(), deep}); });
  EXPECT_NE(m.find("set_palette[1].soil_depth = 2"), std::string::npos) << m;
  m = invalid([&] { t.set_palette({Material::snow()}); });  // index 1 is painted
  EXPECT_NE(m.find("largest index painted on the map (1)"), std::string::npos) << m;
  EXPECT_EQ(t.state_hash(), before);
  ASSERT_EQ(t.palette().size(), 2u);
  EXPECT_EQ(t.palette()[1].name, "mud");
  EXPECT_EQ(t.material_index(3, 3), 1);
}

TEST(MaterialMap, AMaskPaintsOnlyTheTilesItCovers) {
  // A predicate over a rectangle of many tiles that holds at one column, and an image whose
  // only non-zero pixel is that column: both give the map one rect of that column gives
  // (tiles the mask leaves out get no map), and it saves and loads to the same hash (a
  // tile given a map of all 0 hashed as painted, read back as unpainted).
  const std::vector<Material> palette{Material::sand(), Material::mud()};
  Terrain by_rect(one_thread(Material::sand()));
  by_rect.set_palette(palette);
  by_rect.paint_rect({37, 5, 1, 1}, 1);
  Terrain by_predicate(one_thread(Material::sand()));
  by_predicate.set_palette(palette);
  const double x = by_predicate.column_x(37), y = by_predicate.column_y(5);
  by_predicate.paint_where(
      {-100, -100, 200, 200}, [&](double cx, double cy) { return cx == x && cy == y; }, 1);
  std::vector<std::uint8_t> pixels(200 * 200, 0);
  pixels[static_cast<std::size_t>(199 - (5 + 100)) * 200 + (37 + 100)] = 1;  // row 0 is the top (j = 99)
  Terrain by_image(one_thread(Material::sand()));
  by_image.set_palette(palette);
  by_image.paint_image(MaterialImage(200, 200, pixels, "one pixel"), {-100, -100, 200, 200});
  for (const Terrain* t : {&by_predicate, &by_image}) {
    EXPECT_EQ(t->material_index(37, 5), 1);
    EXPECT_EQ(t->state_hash(), by_rect.state_hash());
    EXPECT_EQ(Terrain::load_bytes(t->save_bytes(), "masked").state_hash(), t->state_hash());
  }
}

TEST(MaterialMap, SaveLoadRoundTripOfAPaintedTerrain) {
  Terrain a(one_thread(Material::sand()));
  EXPECT_EQ(a.save_bytes()[8], 5) << "a one-material terrain is written as before maps existed";
  Material packed = packed_sand();
  packed.spray.adhesion = 0.0025;
  packed.unload_modulus = 1e8;
  a.set_palette({Material::sand(), Material::mud(), packed});
  a.paint_rect({0, -40, 40, 80}, 1);
  a.paint_disc(-0.2, 0.0, 0.08, 2);
  for (int k = 0; k < 10; ++k) {
    const shore::EnvelopeRaster env = sphere_envelope(a, -0.15 + 0.03 * k, 0.0, 0.07, 0.1);
    const Imprint im{&env};
    a.step({&im, 1});
  }
  const std::vector<unsigned char> bytes = a.save_bytes();
  EXPECT_EQ(bytes[8], 8);
  Terrain b = Terrain::load_bytes(bytes, "painted");
  EXPECT_EQ(b.state_hash(), a.state_hash());
  ASSERT_EQ(b.palette().size(), 3u);
  EXPECT_EQ(b.palette()[2].name, "packed");
  EXPECT_EQ(b.palette()[2].bekker_kphi, packed.bekker_kphi);
  EXPECT_EQ(b.palette()[2].spray.adhesion, packed.spray.adhesion);
  EXPECT_EQ(b.palette()[2].unload_modulus, packed.unload_modulus);
  for (std::int64_t j = -40; j < 40; ++j)
    for (std::int64_t i = -40; i < 40; ++i) ASSERT_EQ(b.material_index(i, j), a.material_index(i, j));
  for (Terrain* t : {&a, &b}) {
    const shore::EnvelopeRaster env = sphere_envelope(*t, 0.15, 0.0, 0.06, 0.1);
    const Imprint im{&env};
    t->step({&im, 1});
  }
  EXPECT_EQ(b.state_hash(), a.state_hash());
}

TEST(MaterialMap, AFileWithAnIndexBeyondItsPaletteIsRefusedByName) {
  TerrainSettings s = one_thread(Material::sand());
  s.tile_columns = 4;
  Terrain a(s);
  a.set_palette({Material::sand(), Material::mud(), Material::snow()});
  a.paint_rect({0, 0, 4, 4}, 2);  // one tile, painted whole
  std::vector<unsigned char> bytes = a.save_bytes();
  // Layout (terrain_io.cpp): ... painted tiles, u64 layered tile count (0), u64 tile count,
  // one tile of 16 + 3 x 16 x 8 bytes, u64 checksum. The painted tile's last index is the
  // byte before the layered tile count.
  const std::size_t last_index = bytes.size() - 8 - (16 + 3 * 16 * 8) - 8 - 8 - 1;
  ASSERT_EQ(bytes[last_index], 2);
  bytes[last_index] = 7;
  reseal(bytes);
  const std::string m = message_of<shore::FileError>([&] { (void)Terrain::load_bytes(bytes, "repainted.state"); });
  EXPECT_NE(m.find("repainted.state"), std::string::npos) << m;
  EXPECT_NE(m.find("tile (0, 0)"), std::string::npos) << m;
  EXPECT_NE(m.find("column 15 holds index 7, beyond the palette (0 to 2)"), std::string::npos) << m;
}

TEST(MaterialMap, TowedWheelCrossingFromMudIntoSandSettlesToEachSoilsSinkage) {
  // The bench's wheel (D 0.8 m, b 0.2 m, 4 kN) towed over mud, then over sand from x = 1 m.
  const double W = 4000, D = 0.8, b = 0.2;
  const Material mud = Material::mud(), sand = Material::sand();
  Terrain map(one_thread(mud));
  map.set_palette({mud, sand});
  map.paint_rect({100, -50, 400, 100}, 1);
  Terrain mud_alone(one_thread(mud)), sand_alone(one_thread(sand));
  const std::vector<double> on_map = tow(map, W, D, b), on_mud = tow(mud_alone, W, D, b),
                            on_sand = tow(sand_alone, W, D, b);
  // Settled over the last quarter metre of each soil (the wheel's front reaches sand at 0.6 m).
  const double map_mud = mean_depth(on_map, 0.35, 0.6), map_sand = mean_depth(on_map, 1.75, 2.0);
  const double alone_mud = mean_depth(on_mud, 0.35, 0.6), alone_sand = mean_depth(on_sand, 1.75, 2.0);
  const double bekker_mud = bekker::wheel_sinkage_rolling(mud, W, D, b),
               bekker_sand = bekker::wheel_sinkage_rolling(sand, W, D, b);
  std::printf(
      "[ towed ] mud: map %.4f m, alone %.4f m, Bekker rolling %.4f m; sand: map %.4f m, alone %.4f m, "
      "Bekker rolling %.4f m; at the border (x 1 m) %.4f m\n",
      map_mud, alone_mud, bekker_mud, map_sand, alone_sand, bekker_sand, mean_depth(on_map, 1.0, 1.01));
  EXPECT_NEAR(map_mud, alone_mud, 0.01 * alone_mud);
  EXPECT_NEAR(map_sand, alone_sand, 0.01 * alone_sand);
  // The quasi-static column wheel against Bekker's rolling wheel (front half bearing).
  EXPECT_NEAR(map_mud, bekker_mud, 0.1 * bekker_mud);
  EXPECT_NEAR(map_sand, bekker_sand, 0.1 * bekker_sand);
  // It sinks in across the border, not before it.
  EXPECT_NEAR(mean_depth(on_map, 0.4, 0.55), mean_depth(on_mud, 0.4, 0.55), 1e-12);
  const double at_border = mean_depth(on_map, 1.0, 1.01);
  EXPECT_GT(at_border, map_mud);
  EXPECT_LT(at_border, map_sand);
}

TEST(MaterialMap, CorruptMapsInStateFilesGiveAnErrorOrATerrainNeverACrash) {
  // Every byte of a small painted state set to three other values, the checksum made to
  // match: each copy loads as a valid terrain or is refused with a FileError.
  TerrainSettings s = one_thread(Material::sand());
  s.tile_columns = 4;
  Terrain a(s);
  a.set_palette({Material::sand(), Material::mud(), Material::snow()});
  a.paint_rect({0, 0, 6, 3}, 2);
  a.paint_disc(0.0, 0.0, 0.02, 1);
  const std::vector<unsigned char> good = a.save_bytes();
  int refused = 0, loaded = 0;
  for (std::size_t k = 8; k + 8 < good.size(); ++k)
    for (unsigned char v : {0x00, 0x05, 0xff}) {
      if (good[k] == v) continue;
      std::vector<unsigned char> bytes(good.begin(), good.end() - 8);
      bytes[k] = v;
      shore::StateHash sum;
      sum.add_bytes(bytes.data(), bytes.size());
      const std::uint64_t checksum = sum.value();
      bytes.insert(bytes.end(), reinterpret_cast<const unsigned char*>(&checksum),
                   reinterpret_cast<const unsigned char*>(&checksum) + sizeof checksum);
      try {
        const Terrain b = Terrain::load_bytes(bytes, "flipped.state");
        for (std::int64_t j = -2; j < 6; ++j)
          for (std::int64_t i = -2; i < 8; ++i)
            ASSERT_LT(static_cast<std::size_t>(b.material_index(i, j)), b.palette().size());
        ++loaded;
      } catch (const shore::FileError&) {
        ++refused;
      }
    }
  std::printf("[ corrupt ] %zu bytes: %d copies refused, %d loaded\n", good.size(), refused, loaded);
  EXPECT_GT(refused, 0);
  EXPECT_GT(loaded, 0);
}

TEST(MaterialMap, UnloadingAndWallsFollowTheColumnsOwnMaterial) {
  // A box pressed 1 cm into sand (left) and mud (right), then lifted 0.5 mm: sand columns
  // spring back by Wong's k_u = A_u z and still push; mud (A_u = 0) is rigid-plastic and lets
  // go. The rut's walls push by their own soil's k z^(n+1) / (n+1) per unit length.
  const Material sand = Material::sand(), mud = Material::mud();
  ASSERT_GT(sand.unload_modulus, 0.0);
  ASSERT_EQ(mud.unload_modulus, 0.0);
  Terrain t(one_thread(sand));
  t.set_palette({sand, mud});
  t.paint_rect({0, -30, 30, 60}, 1);
  const double depth = 0.01;
  const shore::EnvelopeRaster pressed = box_envelope(-10, -10, 20, 20, -depth);
  const Imprint im{&pressed};
  t.step({&im, 1});
  const double lift = 0.0005;
  const shore::EnvelopeRaster lifted = box_envelope(-10, -10, 20, 20, -depth + lift);
  ContactPatch patch;
  t.contact(lifted, {}, nullptr, patch);
  int bottoms[2] = {0, 0}, walls[2] = {0, 0};
  for (const ContactElement& el : patch.elements) {
    const int index = t.material_index(el.i, el.j);
    const Material& m = t.material_at(el.i, el.j);
    if (el.wall) {
      const double height = t.height(el.i, el.j) - (-depth + lift);
      const double k = m.bekker_kc / patch.patch_width + m.bekker_kphi;
      const double expected = k * std::pow(height, m.bekker_n) / (m.bekker_n + 1.0);  // per m^2 of wall
      EXPECT_NEAR(el.pressure, expected, 1e-9 * expected) << "wall at " << el.i << ", " << el.j;
      ++walls[index];
      continue;
    }
    ++bottoms[index];
    const double z = t.sinkage(el.i, el.j);
    EXPECT_NEAR(z, depth, 1e-12);
    const double k_u = std::max(m.unload_modulus * z, el.pressure / z);  // Wong's A_u z, at least p / z
    EXPECT_NEAR(el.stiffness, k_u, 1e-9 * k_u);
    EXPECT_NEAR(el.preload, el.pressure - k_u * lift, 1e-6 * el.pressure);
  }
  EXPECT_EQ(bottoms[1], 0) << "mud lets go of a lifted box";
  EXPECT_GT(bottoms[0], 150);
  EXPECT_GT(walls[0], 0);
  EXPECT_GT(walls[1], 0);
}
