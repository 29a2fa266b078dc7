// Soil deltas carry the material map: a replica driven only by deltas from a server that
// sets a palette, paints, ploughs and repaints mid-run ends with the server's map, its
// state hash (exact deltas) and its bearing (Bekker, per column); a terrain that never
// paints still sends version 2 deltas; a map that does not fit the replica is refused
// with the replica untouched.

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "shore/core/error.h"
#include "shore/terrain/bekker.h"
#include "shore/terrain/soil_delta.h"
#include "terrain_fixtures.h"

namespace shore::terrain {
namespace {

using testing::box_envelope;
using testing::sphere_envelope;

const shore::GridRect kArea{-5, -5, 90, 50};  // beyond everything painted or ploughed

// The sphere's path: x from 0.2 to 1.4 m over `steps` steps, 3 cm deep.
void plough(Terrain& t, int step, int steps) {
  const double x = 0.2 + 1.2 * step / steps;
  const EnvelopeRaster env = sphere_envelope(t, x, 0.3, 0.15 - 0.03, 0.15);
  Imprint imprint;
  imprint.envelope = &env;
  imprint.velocity.x = 1.2;
  t.step(std::span<const Imprint>(&imprint, 1));
}

std::vector<int> map_of(const Terrain& t) {
  std::vector<int> m;
  for (std::int64_t j = kArea.j0; j < kArea.j0 + kArea.ny; ++j)
    for (std::int64_t i = kArea.i0; i < kArea.i0 + kArea.nx; ++i) m.push_back(t.material_index(i, j));
  return m;
}

std::uint32_t version_of(const std::vector<unsigned char>& delta) {
  std::uint32_t v = 0;
  std::memcpy(&v, delta.data() + 8, sizeof v);
  return v;
}

Material gravel() {
  Material m = Material::sand();
  m.name = "gravel";
  m.bekker_kphi *= 20.0;
  return m;
}

// The server's run, with a delta to the replica every 5 steps: a palette and paint before
// the first step, a repaint (mud over the rut, part of the gravel back to sand) halfway.
struct MapSync {
  Terrain server{testing::coarse_sand()}, replica{testing::coarse_sand()};
  std::uint64_t sent = 0, mirrored = 0;
  std::size_t painted_tiles = 0;
  std::vector<std::uint32_t> versions;

  explicit MapSync(double quantum) {
    sent = mirrored = server.generation();
    server.set_palette({Material::sand(), Material::mud(), gravel()});
    server.paint_rect({0, 0, 40, 8}, 2);     // a gravel strip beside the rut
    server.paint_disc(0.6, 0.3, 0.1, 1);     // a mud hole on the sphere's path
    server.paint_rect({60, 28, 10, 10}, 2);  // plates' ground, away from the rut
    DeltaSettings ds;
    ds.quantum = quantum;
    for (int step = 0; step < 60; ++step) {
      if (step == 30) {
        server.paint_where(
            {20, 10, 30, 10}, [](double x, double) { return x > 0.7; }, 1);
        server.paint_rect({0, 0, 20, 4}, 0);
        server.paint_rect({70, 28, 10, 10}, 1);
      }
      plough(server, step, 60);
      if (step % 5 != 4) continue;
      DeltaStats st;
      const auto delta = SoilDelta::encode(server, sent, ds, &st);
      versions.push_back(version_of(delta));
      painted_tiles += st.painted_tiles;
      sent = server.generation();
      mirrored = SoilDelta::apply(replica, delta, mirrored);
    }
  }
};

// Depth (m) a 10 x 10 column plate carrying `load` N sinks to at column (i0, j0).
double plate_sinkage(const Terrain& t, std::int64_t i0, std::int64_t j0, double load) {
  const EnvelopeRaster env = box_envelope(i0, j0, 10, 10, t.height(i0 + 5, j0 + 5));
  return t.bearing_offset(env, load);
}

TEST(SoilDeltaMaterialMap, ExactReplicaHasTheServersMapAndHash) {
  MapSync run(0.0);
  EXPECT_EQ(map_of(run.replica), map_of(run.server));
  EXPECT_EQ(run.replica.state_hash(), run.server.state_hash());
  ASSERT_EQ(run.replica.palette().size(), 3u);
  EXPECT_EQ(run.replica.palette()[2].bekker_kphi, gravel().bekker_kphi);
  // Only the deltas after a paint carry the map (version 3 before any layer: the plough
  // throws no spray of another material than entry 0); the others are version 2, until the
  // plough's slumping rims carry soil across the mud hole's border, laid there as a layer of
  // its own material (steps 20 on): from then on each delta that repaints is version 5.
  ASSERT_EQ(run.versions.size(), 12u);
  EXPECT_EQ(run.versions[0], 3u);
  EXPECT_EQ(run.versions[1], 2u);
  EXPECT_EQ(run.versions[4], 5u);  // steps 20 to 24: the first layers erosion laid
  EXPECT_EQ(run.versions[6], 5u);  // steps 30 to 34: the repaint
  EXPECT_GT(run.painted_tiles, 0u);
  // The map is read as the server reads it: a plate on the replica's gravel, mud and sand
  // sinks by each one's Bekker law, as on the server (unploughed columns, j 28 to 37).
  const double load = 400.0, b = 0.2, p = load / (b * b);
  for (const auto& [i0, m] : {std::pair{60, 2}, std::pair{70, 1}, std::pair{45, 0}}) {
    EXPECT_EQ(run.replica.material_index(i0 + 5, 33), m);
    const Material& mat = run.replica.palette()[static_cast<std::size_t>(m)];
    const double z = plate_sinkage(run.replica, i0, 28, load);
    EXPECT_EQ(z, plate_sinkage(run.server, i0, 28, load));
    EXPECT_NEAR(z, bekker::plate_sinkage(mat, b, p), 1e-3 * z) << mat.name;
  }
}

// What a renderer reads to follow a map: the indices in bulk, and the tiles repainted since a
// generation (whole tiles, in key order; nothing for a terrain that never painted).
TEST(SoilDeltaMaterialMap, RepaintedTilesAndIndicesInBulk) {
  Terrain t(testing::coarse_sand());  // 16-column tiles
  EXPECT_TRUE(t.painted_since(0).empty());
  t.set_palette({Material::sand(), Material::mud()});
  EXPECT_TRUE(t.painted_since(0).empty());
  t.paint_rect({14, 3, 4, 2}, 1);  // straddles tiles (0, 0) and (1, 0)
  const std::uint64_t seen = t.generation();
  const std::vector<shore::GridRect> tiles = t.painted_since(0);
  ASSERT_EQ(tiles.size(), 2u);
  EXPECT_EQ(tiles[0].i0, 0);
  EXPECT_EQ(tiles[1].i0, 16);
  EXPECT_EQ(tiles[1].nx, 16);
  EXPECT_TRUE(t.painted_since(seen).empty());
  t.paint_disc(t.column_x(40), t.column_y(40), 0.01, 1);  // tile (2, 2) only
  ASSERT_EQ(t.painted_since(seen).size(), 1u);
  EXPECT_EQ(t.painted_since(seen)[0].j0, 32);
  std::vector<std::uint8_t> out(6 * 4);
  t.material_indices({13, 2, 6, 4}, out);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x) {
      const int i = 13 + x, j = 2 + y;
      const bool inside = i >= 14 && i < 18 && j >= 3 && j < 5;
      EXPECT_EQ(out[static_cast<std::size_t>(y * 6 + x)], inside ? 1 : 0) << i << ", " << j;
    }
  EXPECT_THROW(t.material_indices({0, 0, 2, 2}, out), InvalidSetting);
}

TEST(SoilDeltaMaterialMap, QuantisedReplicaHasTheServersMap) {
  MapSync run(1e-4);
  EXPECT_EQ(map_of(run.replica), map_of(run.server));
  ASSERT_EQ(run.replica.palette().size(), 3u);
}

TEST(SoilDeltaMaterialMap, SnapshotCarriesTheMapToALateJoiner) {
  MapSync run(0.0);
  Terrain late(testing::coarse_sand());
  (void)SoilDelta::apply(late, SoilDelta::encode(run.server, 0, DeltaSettings{0.0}), 0);
  EXPECT_EQ(map_of(late), map_of(run.server));
  EXPECT_EQ(late.state_hash(), run.server.state_hash());
  // A terrain loaded from the server's state file sends the same snapshot map.
  const Terrain loaded = Terrain::load_bytes(run.server.save_bytes(), "server");
  Terrain later(testing::coarse_sand());
  (void)SoilDelta::apply(later, SoilDelta::encode(loaded, 0, DeltaSettings{0.0}), 0);
  EXPECT_EQ(map_of(later), map_of(run.server));
  EXPECT_EQ(later.state_hash(), run.server.state_hash());
}

TEST(SoilDeltaMaterialMap, TerrainsThatNeverPaintSendVersion2) {
  Terrain server(testing::coarse_sand());
  for (int step = 0; step < 10; ++step) plough(server, step, 10);
  EXPECT_EQ(version_of(SoilDelta::encode(server, 0, DeltaSettings{0.0})), 2u);
  EXPECT_EQ(version_of(SoilDelta::encode(server, 0, DeltaSettings{})), 2u);
  // Painting index 0 where nothing is painted changes no tile: still nothing to send.
  server.paint_rect({0, 0, 5, 5}, 0);
  EXPECT_EQ(version_of(SoilDelta::encode(server, 0, DeltaSettings{})), 2u);
}

TEST(SoilDeltaMaterialMap, AMapThatDoesNotFitTheReplicaIsRefusedUntouched) {
  Terrain server(testing::coarse_sand());
  server.set_palette({Material::sand(), Material::mud(), gravel()});
  const std::uint64_t after_palette = server.generation();
  server.paint_rect({0, 0, 4, 4}, 2);
  // Sent without its palette (it was set before the delta's start) to a one-material replica.
  Terrain replica(testing::coarse_sand());
  const std::uint64_t hash = replica.state_hash(), generation = replica.generation();
  try {
    (void)SoilDelta::apply(replica, SoilDelta::encode(server, after_palette, DeltaSettings{}), after_palette);
    ADD_FAILURE() << "accepted";
  } catch (const InvalidSetting& e) {
    EXPECT_EQ(e.field(), "terrain.SoilDelta.tile(0, 0).column(0)");
    EXPECT_TRUE(testing::mentions(e.what(), "[0, 0]")) << e.what();
  }
  EXPECT_EQ(replica.state_hash(), hash);
  EXPECT_EQ(replica.generation(), generation);
  EXPECT_EQ(replica.material_index(0, 0), 0);
  // A palette whose soil depth differs from the replica's: refused by name.
  TerrainSettings deep = testing::coarse_sand();
  deep.material.soil_depth *= 2.0;
  Terrain other(deep);
  try {
    (void)SoilDelta::apply(other, SoilDelta::encode(server, 0, DeltaSettings{}), 0);
    ADD_FAILURE() << "accepted";
  } catch (const InvalidSetting& e) {
    EXPECT_EQ(e.field(), "terrain.SoilDelta.palette[0].soil_depth");
  }
  EXPECT_EQ(other.palette().size(), 1u);
  EXPECT_EQ(other.material_index(0, 0), 0);
}

}  // namespace
}  // namespace shore::terrain
