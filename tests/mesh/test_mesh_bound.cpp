// The error bound, exhaustively on small grids: every node's distance to the mesh (located
// in the mesh's triangles, not asked of the extractor) is within the bound in metres, and
// seen from a camera within the bound in pixels; the mesh is a watertight cover of the grid.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mesh_checks.h"
#include "shore/core/error.h"

using namespace shore::mesh;
using namespace shore::mesh::testing;

namespace {

/// A smooth hill, a sharp ridge and a little deterministic roughness: every level of detail
/// has something to keep.
double ground(std::int64_t i, std::int64_t j) {
  const double x = 0.05 * static_cast<double>(i), y = 0.05 * static_cast<double>(j);
  const double hill = 0.3 * std::exp(-((x - 0.8) * (x - 0.8) + (y - 0.6) * (y - 0.6)) / 0.2);
  const double ridge = 0.05 * std::max(0.0, 1.0 - std::abs(x - y - 0.3) / 0.1);
  const std::uint64_t h = (static_cast<std::uint64_t>(i) * 73856093u) ^ (static_cast<std::uint64_t>(j) * 19349663u);
  const double rough = 0.002 * (static_cast<double>(h % 1000) / 1000.0 - 0.5);
  return hill + ridge + rough;
}

void expect_within(const std::vector<double>& err, double bound, double slack, const std::string& what) {
  double worst = 0.0;
  int uncovered = 0;
  for (double e : err) {
    if (e < 0) ++uncovered;
    worst = std::max(worst, e);
  }
  EXPECT_EQ(uncovered, 0) << what << ": nodes outside every triangle";
  EXPECT_LE(worst, bound + slack) << what;
}

struct Case {
  std::int64_t ni, nj;
  int chunk;
};

}  // namespace

TEST(MeshBound, EveryColumnWithinTheBoundInMetres) {
  for (const Case c : {Case{17, 17, 4}, Case{33, 20, 8}, Case{50, 50, 16}, Case{40, 70, 64}, Case{9, 129, 4}})
    for (const double bound : {0.0, 1e-3, 5e-3, 2e-2, 0.2}) {
      FunctionField f = FunctionField::heights(c.ni, c.nj, 0.05, ground);
      MeshSettings s;
      s.max_error = bound;
      s.chunk_cells = c.chunk;
      ChunkedMesh mesh(s);
      mesh.update(f);
      const TriangleMesh m = merge(mesh, f);
      const std::string what = std::to_string(c.ni) + " x " + std::to_string(c.nj) + ", chunk " +
                               std::to_string(c.chunk) + ", bound " + std::to_string(bound);
      expect_within(node_errors(m, f), bound, 1e-12, what);
      for (const std::string& failure : topology_failures(m, c.ni, c.nj)) ADD_FAILURE() << what << ": " << failure;
      // Simplification happened where the bound allows it, and 0 keeps the rough grid whole.
      const std::size_t full = 2 * static_cast<std::size_t>((c.ni - 1) * (c.nj - 1));
      if (bound >= 2e-2) {
        EXPECT_LT(m.triangle_count(), full / 2) << what;
      }
      EXPECT_LE(m.triangle_count(), full) << what;
    }
}

TEST(MeshBound, PlanesCollapseToTheCoarsestTrianglesThatCoverTheGrid) {
  // A tilted plane has no error but rounding anywhere: with a bound of 1e-12 m the mesh is
  // the root's two halves, here over a 64 x 64 grid: 2 triangles.
  FunctionField f =
      FunctionField::heights(65, 65, 0.1, [](std::int64_t i, std::int64_t j) { return 0.01 * i - 0.02 * j; });
  MeshSettings s;
  s.max_error = 1e-12;
  s.chunk_cells = 16;
  ChunkedMesh mesh(s);
  mesh.update(f);
  EXPECT_EQ(mesh.triangle_count(), 2u);
  const TriangleMesh m = merge(mesh, f);
  EXPECT_TRUE(topology_failures(m, 65, 65).empty());
  expect_within(node_errors(m, f), 0.0, 1e-12, "plane");
}

TEST(MeshBound, ThreeDimensionalNodesWithinTheBoundInThreeDimensions) {
  // A wave that leans over: nodes move sideways as well as up, so x and y are not the grid.
  const double h = 0.1;
  auto wave = [&](std::int64_t i, std::int64_t j) {
    const double x = static_cast<double>(i) * h, y = static_cast<double>(j) * h;
    const double phase = 2.0 * std::numbers::pi * (x - 1.5) / 1.2;
    const double envelope = std::exp(-(x - 1.5) * (x - 1.5) / 0.3);
    return std::array<double, 3>{x - 0.12 * envelope * std::sin(phase), y + 0.01 * std::sin(3.0 * y),
                                 0.15 * envelope * std::cos(phase)};
  };
  for (const double bound : {1e-3, 1e-2, 5e-2}) {
    FunctionField f(37, 29, wave, false);
    MeshSettings s;
    s.max_error = bound;
    s.chunk_cells = 8;
    ChunkedMesh mesh(s);
    mesh.update(f);
    const TriangleMesh m = merge(mesh, f);
    expect_within(node_errors(m, f), bound, 1e-12, "leaning wave, bound " + std::to_string(bound));
    EXPECT_TRUE(topology_failures(m, 37, 29).empty());
  }
}

TEST(MeshBound, EveryColumnWithinTheBoundInPixelsFromACamera) {
  const std::int64_t n = 97;
  FunctionField f = FunctionField::heights(n, n, 0.05, ground);
  const std::vector<Camera> cameras = {
      {.position = {2.4, -1.0, 1.2}, .fov_y_deg = 45.0, .viewport_height = 1080},  // beyond the edge, low
      {.position = {1.0, 1.0, 0.5}, .fov_y_deg = 60.0, .viewport_height = 720},    // just above the hill
      {.position = {0.2, 4.6, 0.05}, .fov_y_deg = 30.0, .viewport_height = 2160},  // grazing
  };
  for (const double px : {0.5, 1.0, 4.0})
    for (const Camera& cam : cameras) {
      MeshSettings s;
      s.max_error_pixels = px;
      s.chunk_cells = 16;
      ChunkedMesh mesh(s);
      mesh.update(f, &cam);
      const TriangleMesh m = merge(mesh, f);
      const std::vector<double> angle = node_angles(m, f, cam);
      const std::string what = "camera at " + std::to_string(cam.position.x) + ", " + std::to_string(cam.position.y) +
                               ", " + std::to_string(cam.position.z) + ", " + std::to_string(px) + " px";
      std::vector<double> pixels;
      for (double a : angle) pixels.push_back(a < 0 ? a : a * cam.pixels_per_radian());
      expect_within(pixels, px, 1e-9, what);
      for (const std::string& failure : topology_failures(m, n, n)) ADD_FAILURE() << what << ": " << failure;
      EXPECT_LT(m.triangle_count(), 2u * (n - 1) * (n - 1)) << what;
    }
}

TEST(MeshBound, FartherCamerasNeedFewerTriangles) {
  FunctionField f = FunctionField::heights(129, 129, 0.05, ground);
  std::size_t previous = 0;
  for (const double d : {1.0, 4.0, 16.0, 64.0}) {
    ChunkedMesh mesh;
    const Camera cam{.position = {3.2, -d, 0.5 * d}};
    mesh.update(f, &cam);
    if (previous) {
      EXPECT_LT(mesh.triangle_count(), previous) << d;
    }
    previous = mesh.triangle_count();
  }
}

TEST(MeshBound, HolesDropOnlyTheTrianglesThatTouchThem) {
  const std::int64_t n = 33;
  FunctionField f = FunctionField::heights(n, n, 0.1, [](std::int64_t i, std::int64_t j) {
    const bool hole = (i - 20) * (i - 20) + (j - 12) * (j - 12) < 16;
    return hole ? std::numeric_limits<double>::quiet_NaN() : 0.01 * i;
  });
  MeshSettings s;
  s.max_error = 0.01;
  s.chunk_cells = 8;
  ChunkedMesh mesh(s);
  mesh.update(f);
  const TriangleMesh m = merge(mesh, f);
  EXPECT_TRUE(topology_failures(m, n, n, true).empty());
  for (double p : m.positions) EXPECT_TRUE(std::isfinite(p));
  const std::vector<double> err = node_errors(m, f);
  for (std::int64_t j = 0; j < n; ++j)
    for (std::int64_t i = 0; i < n; ++i) {
      const bool hole = std::isnan(f.at(i, j)[2]);
      const bool next_to_hole = [&] {
        for (int dj = -1; dj <= 1; ++dj)
          for (int di = -1; di <= 1; ++di)
            if (i + di >= 0 && j + dj >= 0 && i + di < n && j + dj < n && std::isnan(f.at(i + di, j + dj)[2]))
              return true;
        return false;
      }();
      if (hole) continue;
      if (!next_to_hole) {
        EXPECT_GE(err[static_cast<std::size_t>(j * n + i)], 0.0) << "node " << i << "," << j << " dropped";
      }
      EXPECT_LE(err[static_cast<std::size_t>(j * n + i)], 0.01 + 1e-12);
    }
}

TEST(MeshSettings, BadValuesAreNamed) {
  auto field_of = [](auto&& edit) {
    MeshSettings s;
    edit(s);
    try {
      ChunkedMesh m(s);
    } catch (const shore::InvalidSetting& e) {
      return e.field();
    }
    return std::string("accepted");
  };
  EXPECT_EQ(field_of([](MeshSettings& s) { s.max_error = -1; }), "mesh.MeshSettings.max_error");
  EXPECT_EQ(field_of([](MeshSettings& s) { s.max_error_pixels = 0; }), "mesh.MeshSettings.max_error_pixels");
  EXPECT_EQ(field_of([](MeshSettings& s) { s.chunk_cells = 48; }), "mesh.MeshSettings.chunk_cells");
  EXPECT_EQ(field_of([](MeshSettings& s) { s.chunk_cells = 2048; }), "mesh.MeshSettings.chunk_cells");
  EXPECT_EQ(field_of([](MeshSettings& s) { s.distance_steps_per_octave = 0; }),
            "mesh.MeshSettings.distance_steps_per_octave");
  ChunkedMesh mesh;
  FunctionField f = FunctionField::heights(5, 5, 1.0, [](std::int64_t, std::int64_t) { return 0.0; });
  Camera bad;
  bad.fov_y_deg = 180;
  EXPECT_THROW(mesh.update(f, &bad), shore::InvalidSetting);
  FunctionField tiny = FunctionField::heights(1, 5, 1.0, [](std::int64_t, std::int64_t) { return 0.0; });
  EXPECT_THROW(mesh.update(tiny), shore::InvalidSetting);
  mesh.update(f);
  FunctionField other = FunctionField::heights(6, 5, 1.0, [](std::int64_t, std::int64_t) { return 0.0; });
  EXPECT_THROW(mesh.update(other), shore::InvalidSetting);  // one mesh follows one field
}
