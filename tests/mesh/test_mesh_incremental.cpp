// Meshes that follow a changing surface: a wheel rolling over soil (Terrain::step) and the
// seed water stepping, with the camera moving. Each update must leave exactly the mesh a
// build from scratch gives, report exactly the chunks that differ, stay watertight across
// tile borders and changes of detail, and never read the untouched parts of a large field.
#include <gtest/gtest.h>

#include "mesh_checks.h"
#include "shore/scenes/mesh_cases.h"
#include "shore/terrain/mesh_field.h"
#include "shore/water/mesh_field.h"

using namespace shore;
using namespace shore::mesh;
using namespace shore::mesh::testing;

namespace {

terrain::TerrainSettings soil_with_small_tiles() {
  terrain::TerrainSettings s;
  s.cell = 0.01;
  s.tile_columns = 16;  // the wheel crosses many tile borders
  return s;
}

constexpr shore::GridRect kRegion{-20, -40, 140, 81};  // 1.39 m x 0.8 m around the track

void expect_same_chunks(const std::map<ChunkKey, Chunk>& a, const std::map<ChunkKey, Chunk>& b,
                        const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (auto ia = a.begin(), ib = b.begin(); ia != a.end(); ++ia, ++ib) {
    ASSERT_TRUE(ia->first == ib->first) << what;
    EXPECT_EQ(ia->second.indices, ib->second.indices) << what;
    EXPECT_EQ(ia->second.nodes, ib->second.nodes) << what;
    EXPECT_EQ(ia->second.positions, ib->second.positions) << what;
    EXPECT_EQ(ia->second.normals, ib->second.normals) << what;
  }
}

/// The camera rides 0.4 m behind and 0.3 m above the wheel.
Camera chase(const scenes::RollingWheel& w) { return {.position = {w.x() - 0.4, w.y(), 0.3}}; }

}  // namespace

TEST(MeshIncremental, AfterAWheelPassesEachUpdateEqualsABuildFromScratch) {
  terrain::Terrain soil(soil_with_small_tiles());
  scenes::RollingWheel wheel(soil, 0.0, 0.0);
  terrain::TerrainField field(soil, kRegion);
  MeshSettings s;
  s.chunk_cells = 16;
  ChunkedMesh mesh(s);
  std::map<ChunkKey, Chunk> renderer;  // what a renderer holds after applying every update
  std::size_t rebuilt = 0, updates = 0;
  for (int frame = 0; frame < 24; ++frame) {
    for (int k = 0; k < 4; ++k) wheel.step();  // 60 frames/s of 240 substeps/s
    const Camera cam = chase(wheel);
    const MeshUpdate& u = mesh.update(field, &cam);
    apply(renderer, mesh, u);
    rebuilt += u.changed.size();
    ++updates;
    if (frame % 6 != 5) continue;
    terrain::TerrainField fresh_field(soil, kRegion);
    ChunkedMesh fresh(s);
    fresh.update(fresh_field, &cam);
    expect_same_chunks(mesh.chunks(), fresh.chunks(), "frame " + std::to_string(frame));
    expect_same_chunks(renderer, mesh.chunks(), "renderer copy, frame " + std::to_string(frame));
  }
  EXPECT_GT(soil.volume().compacted, 0.0) << "the wheel pressed the soil";
  // Incremental: most chunks are kept from one frame to the next.
  EXPECT_LT(static_cast<double>(rebuilt) / updates, 0.5 * static_cast<double>(mesh.chunks().size()));
}

TEST(MeshIncremental, MetresBoundUpdatesEqualScratchToo) {
  terrain::Terrain soil(soil_with_small_tiles());
  scenes::RollingWheel wheel(soil, 0.0, 0.0);
  terrain::TerrainField field(soil, kRegion);
  MeshSettings s;
  s.max_error = 5e-4;
  s.chunk_cells = 8;
  ChunkedMesh mesh(s);
  for (int frame = 0; frame < 12; ++frame) {
    for (int k = 0; k < 8; ++k) wheel.step();
    mesh.update(field);
  }
  terrain::TerrainField fresh_field(soil, kRegion);
  ChunkedMesh fresh(s);
  fresh.update(fresh_field);
  expect_same_chunks(mesh.chunks(), fresh.chunks(), "metres bound");
  const TriangleMesh m = merge(mesh, field);
  std::vector<double> err = node_errors(m, field);
  for (double e : err) {
    EXPECT_GE(e, 0.0);
    EXPECT_LE(e, 5e-4 + 1e-12);
  }
}

TEST(MeshIncremental, WatertightAcrossTileBordersAndChangesOfDetail) {
  terrain::Terrain soil(soil_with_small_tiles());
  scenes::RollingWheel wheel(soil, 0.0, 0.0);
  for (int k = 0; k < 120; ++k) wheel.step();
  terrain::TerrainField field(soil, kRegion);
  MeshSettings s;
  s.chunk_cells = 8;  // chunks smaller than tiles: borders of both inside the rut
  ChunkedMesh mesh(s);
  const Camera cam{.position = {0.1, 0.0, 0.15}};  // close: detail falls off along the rut
  mesh.update(field, &cam);
  const TriangleMesh m = merge(mesh, field);
  for (const std::string& failure : topology_failures(m, kRegion.nx, kRegion.ny)) ADD_FAILURE() << failure;
  // Several levels of detail meet: triangles of many sizes, chunks of more than one size.
  std::set<std::int64_t> sizes;
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const GridNode a = node_of(m.nodes[m.indices[3 * t]], kRegion.nx),
                   b = node_of(m.nodes[m.indices[3 * t + 1]], kRegion.nx),
                   c = node_of(m.nodes[m.indices[3 * t + 2]], kRegion.nx);
    sizes.insert(std::abs(cross(a, b, c)));
  }
  EXPECT_GE(sizes.size(), 5u);
  std::set<std::int64_t> chunk_sizes;
  for (const auto& [key, chunk] : mesh.chunks()) chunk_sizes.insert(key.cells);
  EXPECT_GE(chunk_sizes.size(), 2u);
  const std::vector<double> angle = node_angles(m, field, cam);
  for (double a : angle) EXPECT_LE(a * cam.pixels_per_radian(), 1.0 + 1e-9);
  // Normals: unit length, and up on ground that is nowhere steeper than vertical.
  for (std::size_t v = 0; v < m.nodes.size(); ++v) {
    const double nx = m.normals[3 * v], ny = m.normals[3 * v + 1], nz = m.normals[3 * v + 2];
    EXPECT_NEAR(nx * nx + ny * ny + nz * nz, 1.0, 1e-6);
    EXPECT_GT(nz, 0.0);
  }
}

TEST(MeshIncremental, SeedWaterFollowedStepByStepEqualsScratch) {
  const std::unique_ptr<water::Surface> surface = scenes::seed_water();
  water::SurfaceField field(*surface);
  ChunkedMesh mesh;
  Camera cam = scenes::seed_water_camera();
  for (int k = 0; k < 10; ++k) {
    surface->step(0.4);
    cam.position.y += 0.5;  // walking towards the pool
    mesh.update(field, &cam);
  }
  water::SurfaceField fresh_field(*surface);
  ChunkedMesh fresh;
  fresh.update(fresh_field, &cam);
  expect_same_chunks(mesh.chunks(), fresh.chunks(), "seed water");
  // A still camera over a still surface changes nothing.
  const MeshUpdate& still = mesh.update(field, &cam);
  EXPECT_TRUE(still.changed.empty());
  EXPECT_TRUE(still.removed.empty());
}

TEST(MeshIncremental, GroundThatIsNotFlatIsReadWholeAndStaysWithinTheBound) {
  // Lattice-noise ground has no base plane: the first update reads the whole region, and
  // later ones only what the wheel changed.
  terrain::TerrainSettings ts = soil_with_small_tiles();
  terrain::LatticeNoiseSettings noise;
  noise.amplitude = 0.03;
  noise.spacing = 0.3;
  noise.octaves = 3;
  ts.base = std::make_shared<terrain::LatticeNoise>(noise);
  terrain::Terrain soil(ts);
  terrain::TerrainField field(soil, kRegion);
  MeshSettings s;
  s.max_error = 1e-3;
  s.chunk_cells = 16;
  ChunkedMesh mesh(s);
  const MeshUpdate& first = mesh.update(field);
  EXPECT_GE(first.nodes_read, static_cast<std::int64_t>(kRegion.nx) * kRegion.ny);
  scenes::RollingWheel wheel(soil, 0.0, 0.0);
  for (int k = 0; k < 8; ++k) wheel.step();
  const MeshUpdate& later = mesh.update(field);
  EXPECT_LT(later.nodes_read, static_cast<std::int64_t>(kRegion.nx) * kRegion.ny / 2);
  terrain::TerrainField fresh_field(soil, kRegion);
  ChunkedMesh fresh(s);
  fresh.update(fresh_field);
  expect_same_chunks(mesh.chunks(), fresh.chunks(), "noise ground");
  const TriangleMesh m = merge(mesh, field);
  for (double e : node_errors(m, field)) {
    EXPECT_GE(e, 0.0);
    EXPECT_LE(e, 1e-3 + 1e-12);
  }
  EXPECT_TRUE(topology_failures(m, kRegion.nx, kRegion.ny).empty());
}

TEST(MeshIncremental, ALargeFieldCostsItsTouchedTilesOnly) {
  // 1 km x 1 km of 1 cm columns (10^10 nodes) with three edits: the mesh reads the tiles
  // around them and a few nodes more, never the field.
  terrain::Terrain soil{terrain::TerrainSettings{}};
  const shore::GridRect region{0, 0, 100001, 100001};
  terrain::TerrainField field(soil, region);
  soil.set_height(50000, 50000, -0.02);
  soil.set_height(50001, 50000, -0.02);
  soil.set_height(70000, 20000, 0.05);
  ChunkedMesh mesh;
  const Camera cam{.position = {500.0, 500.0, 2.0}};
  const MeshUpdate& u = mesh.update(field, &cam);
  EXPECT_LT(u.nodes_read, 200000);
  EXPECT_LT(u.triangles, 20000u);
  EXPECT_GT(u.triangles, 2u);
  // An edit far from the others changes a handful of chunks.
  soil.set_height(10, 10, 0.01);
  const MeshUpdate& v = mesh.update(field, &cam);
  EXPECT_LT(v.nodes_read, 50000);
  EXPECT_FALSE(v.changed.empty());
  EXPECT_LT(v.changed.size(), 40u);
}

TEST(MeshIncremental, TheLargeFieldsRutIsWithinAPixelFromTwoMetresAbove) {
  // The large field's structure (1 km at 1 cm, flat, one rut) with a 10 m rut: around the
  // rut every column is covered and within a pixel of a 1080-line view.
  const scenes::LargeField f = scenes::large_field(1000.0, 10.0);
  terrain::TerrainField field(*f.soil, f.region);
  const Camera cam = scenes::large_field_camera(f);
  ChunkedMesh mesh;
  mesh.update(field, &cam);
  EXPECT_LT(mesh.triangle_count(), 100000u);
  const TriangleMesh m = merge(mesh, field);
  const std::int64_t i0 = f.soil->column_i(f.rut_x0) - 30, j0 = f.soil->column_j(f.rut_y) - 40;
  const GridRect window{i0, j0, static_cast<int>(f.soil->column_i(f.rut_x1) + 30 - i0), 81};
  const std::vector<double> angle = node_angles(m, field, cam, window);
  double worst = 0.0;
  for (double a : angle) {
    ASSERT_GE(a, 0.0) << "a column outside the mesh";
    worst = std::max(worst, a * cam.pixels_per_radian());
  }
  EXPECT_LE(worst, 1.0 + 1e-9);
  EXPECT_GT(worst, 0.2) << "the bound is used, not a full-resolution mesh near the camera";
}

TEST(MeshIncremental, MeshesAndTheCouplingEachSeeEveryChange) {
  // A mesh takes changes through Terrain::changed_since, the coupling through
  // take_changed: neither starves the other.
  terrain::Terrain soil(soil_with_small_tiles());
  terrain::TerrainField a(soil, kRegion), b(soil, kRegion);
  ChunkedMesh ma, mb;
  ma.update(a);
  mb.update(b);
  scenes::RollingWheel wheel(soil, 0.0, 0.0);
  for (int k = 0; k < 20; ++k) wheel.step();
  EXPECT_FALSE(soil.take_changed().empty());  // the coupling's view, consumed
  EXPECT_FALSE(ma.update(a).changed.empty());
  EXPECT_FALSE(mb.update(b).changed.empty());
  expect_same_chunks(ma.chunks(), mb.chunks(), "two meshes of one soil");
}
