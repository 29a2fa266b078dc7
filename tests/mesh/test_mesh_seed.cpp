// The seed paper's comparison (Finch & Bishop's simplification of its 50 x 50 water: 4802
// triangles became 2431 with no visible loss): the same surface after a drop, seen the way
// its figures see it, at 1 pixel of a 1080-line view, must need at most half the triangles,
// with every node within the pixel bound.
#include <gtest/gtest.h>

#include "mesh_checks.h"
#include "shore/scenes/mesh_cases.h"
#include "shore/water/mesh_field.h"

using namespace shore;
using namespace shore::mesh;
using namespace shore::mesh::testing;

TEST(SeedWater, OnePixelFromThePapersViewpointHalvesTheTriangles) {
  const std::unique_ptr<water::Surface> surface = scenes::seed_water();
  water::SurfaceField field(*surface);
  const Camera cam = scenes::seed_water_camera();
  ChunkedMesh mesh;  // 1 pixel
  mesh.update(field, &cam);
  const TriangleMesh m = merge(mesh, field);

  std::vector<std::uint32_t> indices;
  surface->triangles(indices);
  ASSERT_EQ(indices.size() / 3, scenes::kSeedFullTriangles);
  RecordProperty("triangles", static_cast<int>(m.triangle_count()));
  EXPECT_LE(m.triangle_count(), scenes::kSeedFullTriangles / 2)
      << "the paper halved them (4802 -> 2431); ratio " << double(m.triangle_count()) / scenes::kSeedFullTriangles;

  // The surface really is disturbed (not a flat pool that any method collapses) ...
  double highest = 0.0;
  for (int j = 0; j < 50; ++j)
    for (int i = 0; i < 50; ++i) highest = std::max(highest, std::abs(surface->height(i, j)));
  EXPECT_GT(highest, 0.3);
  // ... and no node is farther than a pixel from the mesh, seen from the eye.
  const std::vector<double> angle = node_angles(m, field, cam);
  for (std::size_t k = 0; k < angle.size(); ++k) {
    ASSERT_GE(angle[k], 0.0) << "node " << k << " outside the mesh";
    EXPECT_LE(angle[k] * cam.pixels_per_radian(), 1.0 + 1e-9) << "node " << k;
  }
  for (const std::string& failure : topology_failures(m, 50, 50)) ADD_FAILURE() << failure;
}
