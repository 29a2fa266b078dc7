// Volume per material through erosion across borders: the moved soil keeps its material
// (docs/terrain.md, "Erosion across a border"). Each material's volume is computed here from
// the public API alone (heights, bedrock, sinkage, indices and layer boundaries), not from
// the erosion's own bookkeeping.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <vector>

#include "shore/terrain/soil_delta.h"
#include "shore/terrain/terrain.h"
#include "terrain_fixtures.h"

using namespace shore::terrain;
using namespace shore::terrain::testing;

namespace {

constexpr double kCell = 0.01;
constexpr int kSand = 0, kGravel = 1, kMud = 2;
const shore::GridRect kWorld{-40, -40, 80, 80};

/// m^3 of each palette entry over kWorld: a column's soil above bedrock is its painted
/// material where it is not layered; where it is, its top layer (the painted index) is the
/// boundary less the sinkage thick (within [0, soil]) and the rest is the lower index's.
/// Summed in long double, column by column in a fixed order.
std::array<long double, 3> volumes(const Terrain& t) {
  std::array<long double, 3> v{};
  for (std::int64_t j = kWorld.j0; j < kWorld.j0 + kWorld.ny; ++j)
    for (std::int64_t i = kWorld.i0; i < kWorld.i0 + kWorld.nx; ++i) {
      const double soil = t.height(i, j) - t.bedrock(i, j);
      const int lower = t.lower_index(i, j);
      if (lower < 0) {
        v[static_cast<std::size_t>(t.material_index(i, j))] += soil;
        continue;
      }
      const double top = std::clamp(t.layer_boundary(i, j) - t.sinkage(i, j), 0.0, soil);
      v[static_cast<std::size_t>(t.material_index(i, j))] += top;
      v[static_cast<std::size_t>(lower)] += soil - top;
    }
  for (long double& x : v) x *= kCell * kCell;
  return v;
}

TerrainSettings settings() {
  TerrainSettings s;
  s.cell = kCell;
  s.tile_columns = 32;
  s.threads = 1;
  s.max_erosion_passes = 40;
  s.material = Material::sand();
  return s;
}

/// Sand (entry 0, repose 25 degrees), gravel (x < 0, repose 40 degrees) and mud (x >= 0,
/// repose 63 degrees, at sand's soil depth); a 60 degree sand cone 10 cm in radius on their
/// border: each cone column is sand over the ground's material, the sand as thick as the cone.
void paint_cone(Terrain& t) {
  Material gravel = Material::sand();
  gravel.name = "gravel";
  gravel.theta_out = 40.0 * std::numbers::pi / 180;
  gravel.theta_stop = gravel.theta_out;
  gravel.bekker_kphi *= 4.0;
  Material mud = Material::mud();
  mud.soil_depth = Material::sand().soil_depth;
  t.set_palette({Material::sand(), gravel, mud});
  t.paint_rect({-40, -40, 40, 80}, kGravel);
  t.paint_rect({0, -40, 40, 80}, kMud);
  const double r = 0.10, slope = std::numbers::pi / 3;
  for (std::int64_t j = -12; j <= 12; ++j)
    for (std::int64_t i = -12; i <= 12; ++i) {
      const double d = std::hypot(t.column_x(i), t.column_y(j));
      if (d >= r) continue;
      const double h = (r - d) * std::tan(slope);
      t.set_height(i, j, h);
      t.paint_layer_rect({i, j, 1, 1}, t.material_index(i, j), h);
      t.paint_rect({i, j, 1, 1}, kSand);
    }
}

/// Steepest slope (rad) from a sand-topped column to any neighbour, on the side x < 0
/// (gravel) or x >= 0 (mud).
double steepest_sand(const Terrain& t, bool gravel_side) {
  double steepest = 0.0;
  for (std::int64_t j = -30; j < 30; ++j)
    for (std::int64_t i = gravel_side ? -30 : 0; i < (gravel_side ? 0 : 30); ++i) {
      if (t.exposed_index(i, j) != kSand) continue;
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          if (!di && !dj) continue;
          const double drop = t.height(i, j) - t.height(i + di, j + dj);
          steepest = std::max(steepest, std::atan(drop / (kCell * std::hypot(di, dj))));
        }
    }
  return steepest;
}

/// m^3 of sand in top layers beyond the cone (what the rule before this one would have
/// turned into the ground's material).
double sand_beyond_cone(const Terrain& t) {
  double v = 0.0;
  for (std::int64_t j = -30; j < 30; ++j)
    for (std::int64_t i = -30; i < 30; ++i)
      if (std::hypot(t.column_x(i), t.column_y(j)) >= 0.10 && t.material_index(i, j) == kSand &&
          t.lower_index(i, j) >= 0)
        v += std::clamp(t.layer_boundary(i, j) - t.sinkage(i, j), 0.0, t.height(i, j) - t.bedrock(i, j));
  return v * kCell * kCell;
}

/// Columns outside the cone that now hold sand over `lower`.
int sand_over(const Terrain& t, int lower) {
  int n = 0;
  for (std::int64_t j = -30; j < 30; ++j)
    for (std::int64_t i = -30; i < 30; ++i)
      if (std::hypot(t.column_x(i), t.column_y(j)) >= 0.10 && t.material_index(i, j) == kSand &&
          t.lower_index(i, j) == lower)
        ++n;
  return n;
}

/// The cone slumped for `steps` steps under a body hovering 1 cm above its top.
void slump(Terrain& t, int steps) {
  const shore::EnvelopeRaster env = box_envelope(-20, -20, 40, 40, t.height(0, 0) + 0.01);
  const Imprint im{&env};
  for (int k = 0; k < steps; ++k) t.step({&im, 1});
}

}  // namespace

TEST(MaterialVolume, TheLayersErosionLaysAreTheSameForAnyThreadCount) {
  TerrainSettings two = settings();
  two.threads = 2;
  two.parallel_min_columns = 0;  // every region's rows on the team
  Terrain one_thread(settings()), two_threads(two);
  paint_cone(one_thread);
  paint_cone(two_threads);
  const double top = one_thread.height(0, 0);
  slump(one_thread, 30);
  slump(two_threads, 30);
  EXPECT_EQ(two_threads.state_hash(), one_thread.state_hash());
  EXPECT_LT(one_thread.height(0, 0), top - 0.01) << "the steps slumped the cone";
  for (Terrain* t : {&one_thread, &two_threads}) (void)t->relax({-35, -35, 70, 70});
  EXPECT_EQ(two_threads.state_hash(), one_thread.state_hash());
  EXPECT_GT(sand_over(one_thread, kGravel) + sand_over(one_thread, kMud), 0) << "sand lies on the ground";
}

TEST(MaterialVolume, ASandConeOnAGravelMudBorderKeepsEachMaterialsVolume) {
  Terrain server(settings()), replica(settings());
  std::uint64_t sent = server.generation(), mirrored = sent;
  const auto sync = [&] {
    DeltaSettings exact;
    exact.quantum = 0.0;
    const std::vector<unsigned char> delta = SoilDelta::encode(server, sent, exact);
    sent = server.generation();
    mirrored = SoilDelta::apply(replica, delta, mirrored);
  };
  paint_cone(server);
  sync();
  const std::array<long double, 3> before = volumes(server);

  // Slumping step after step under a body hovering 1 cm above it (the steps' erosion, its
  // deposits loosened, no column touched), then relaxed to rest.
  const double top = server.height(0, 0);
  const shore::EnvelopeRaster env = box_envelope(-20, -20, 40, 40, top + 0.01);
  const Imprint im{&env};
  for (int k = 0; k < 30; ++k) {
    server.step({&im, 1});
    if (k % 10 == 9) sync();
  }
  const std::array<long double, 3> stepped = volumes(server);
  std::printf("[ volume ] the cone's top %.4f m, %.4f after 30 steps\n", top, server.height(0, 0));
  EXPECT_LT(server.height(0, 0), top - 0.01) << "the steps slumped the cone";
  int rounds = 0;
  while (server.relax({-35, -35, 70, 70}).erosion_passes == server.settings().max_erosion_passes && rounds < 400)
    ++rounds;
  sync();
  const std::array<long double, 3> after = volumes(server);

  const char* names[] = {"sand", "gravel", "mud"};
  for (std::size_t m = 0; m < 3; ++m)
    std::printf("[ volume ] %-6s %.17Lg m^3 before, %+.3Lg after 30 steps, %+.3Lg at rest\n", names[m], before[m],
                stepped[m] - before[m], after[m] - before[m]);
  // The representation's rounding (each height and boundary a double, a few ulps of a
  // column's ~1 m of soil per move): far below a single cell's worth of sand moved.
  for (std::size_t m = 0; m < 3; ++m) {
    EXPECT_NEAR(static_cast<double>(stepped[m]), static_cast<double>(before[m]), 1e-15) << names[m];
    EXPECT_NEAR(static_cast<double>(after[m]), static_cast<double>(before[m]), 1e-15) << names[m];
  }
  // The sand went onto both grounds and lies there as sand over them.
  const int on_gravel = sand_over(server, kGravel), on_mud = sand_over(server, kMud);
  const double beyond = sand_beyond_cone(server);
  std::printf("[ volume ] %d columns beyond the cone hold sand over gravel, %d over mud: %.3g m^3 of sand\n", on_gravel,
              on_mud, beyond);
  EXPECT_GT(beyond, 1e-4) << "a share of the cone's sand moved onto the ground";
  EXPECT_GT(on_gravel, 20);
  EXPECT_GT(on_mud, 20);
  // Sand keeps its own repose angle on either ground (gravel's 40, mud's 63 degrees).
  const double degree = std::numbers::pi / 180, sand = Material::sand().theta_out;
  const double on_g = steepest_sand(server, true), on_m = steepest_sand(server, false);
  std::printf("[ volume ] steepest sand slope %.2f deg over gravel, %.2f over mud (sand's repose %.2f)\n",
              on_g / degree, on_m / degree, sand / degree);
  EXPECT_NEAR(on_g, sand, degree);
  EXPECT_NEAR(on_m, sand, degree);

  // Saved and loaded: the same bytes and hash; the replica fed exact deltas: the same layers.
  const std::vector<unsigned char> bytes = server.save_bytes();
  const Terrain loaded = Terrain::load_bytes(bytes, "the slumped cone");
  EXPECT_EQ(loaded.save_bytes(), bytes);
  EXPECT_EQ(loaded.state_hash(), server.state_hash());
  EXPECT_EQ(replica.state_hash(), server.state_hash());
  for (std::int64_t j = -30; j < 30; ++j)
    for (std::int64_t i = -30; i < 30; ++i) {
      ASSERT_EQ(replica.material_index(i, j), server.material_index(i, j)) << i << ", " << j;
      ASSERT_EQ(replica.lower_index(i, j), server.lower_index(i, j)) << i << ", " << j;
      ASSERT_EQ(replica.layer_boundary(i, j), server.layer_boundary(i, j)) << i << ", " << j;
      ASSERT_EQ(loaded.layer_boundary(i, j), server.layer_boundary(i, j)) << i << ", " << j;
    }
}
