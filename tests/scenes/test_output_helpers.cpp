// The scenes' output helpers against outside references: plane geometry for the mesh
// export, stb's own PNG reader for the PNG writer, Bullet's ray test for the ground height,
// the colour maps for the pictures' colour bars.
#include <gtest/gtest.h>

#include <stb_image.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "shore/core/error.h"
#include "shore/scenes/height_grid.h"
#include "shore/scenes/image.h"
#include "shore/scenes/mesh.h"
#include "shore/scenes/picture.h"
#include "shore/scenes/report.h"
#include "shore/scenes/rigid_ground.h"
#include "shore/scenes/runner.h"
#include "shore/scenes/world.h"

namespace fs = std::filesystem;
using namespace shore::scenes;

namespace {

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::path(testing::TempDir()) / ("shore_scene_helpers_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

HeightGrid plane(int nx, int ny, double cell, double a, double b, double c) {
  HeightGrid g(nx, ny, cell, -0.3, 0.2);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) g.at(i, j) = a * g.x(i) + b * g.y(j) + c;
  return g;
}

TEST(HeightGrid, BilinearSampleOfAPlaneIsExact) {
  const HeightGrid g = plane(5, 4, 0.1, 0.3, -0.7, 0.05);
  for (double x : {-0.3, -0.21, 0.0, 0.1})
    for (double y : {0.2, 0.26, 0.45})
      EXPECT_NEAR(g.sample_world(x, y), 0.3 * x - 0.7 * y + 0.05, 1e-12) << x << ", " << y;
}

TEST(HeightGrid, RejectsBadSizes) {
  EXPECT_THROW(HeightGrid(0, 3, 0.1, 0, 0), shore::InvalidSetting);
  EXPECT_THROW(HeightGrid(3, 3, -0.1, 0, 0), shore::InvalidSetting);
}

TEST(Colours, DivergingMapIsBlueForLoweredRedForRaisedNeutralForUntouched) {
  const Rgb low = diverging_colour(-1.0), mid = diverging_colour(0.0), high = diverging_colour(1.0);
  EXPECT_GT(low.b, low.r + 80);
  EXPECT_GT(high.r, high.b + 80);
  EXPECT_LT(std::abs(mid.r - mid.b), 40);
  EXPECT_EQ(diverging_colour(-5.0), low);  // clamped
}

TEST(Png, RoundTripsThroughStbReader) {
  Image img(7, 5, {10, 20, 30});
  img.put(3, 2, {250, 0, 128});
  draw_text(img, 0, 0, "A", {1, 2, 3}, 1);
  const fs::path p = write_png(temp_dir("png") / "x.png", img);
  int w = 0, h = 0, n = 0;
  unsigned char* data = stbi_load(p.c_str(), &w, &h, &n, 3);
  ASSERT_NE(data, nullptr);
  ASSERT_EQ(w, 7);
  ASSERT_EQ(h, 5);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const unsigned char* px = data + 3 * (y * w + x);
      EXPECT_EQ((Rgb{px[0], px[1], px[2]}), img.at(x, y)) << x << ", " << y;
    }
  stbi_image_free(data);
  EXPECT_FALSE(fs::exists(p.string() + ".tmp"));
}

TEST(Png, UnwritablePathThrowsFileError) {
  EXPECT_THROW(write_png("/nonexistent-dir/x.png", Image(2, 2)), shore::FileError);
}

struct ObjMesh {
  std::vector<std::array<double, 3>> v;
  std::vector<std::array<double, 3>> vn;
  std::vector<std::array<int, 3>> f;
};
ObjMesh read_obj(const fs::path& p) {
  ObjMesh m;
  std::ifstream in(p);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v") {
      std::array<double, 3> v{};
      s >> v[0] >> v[1] >> v[2];
      m.v.push_back(v);
    } else if (tag == "vn") {
      std::array<double, 3> n{};
      s >> n[0] >> n[1] >> n[2];
      m.vn.push_back(n);
    } else if (tag == "f") {  // "a b c" or "a//a b//b c//c"
      std::array<int, 3> f{};
      for (int& k : f) {
        std::string word;
        s >> word;
        k = std::stoi(word.substr(0, word.find('/')));
      }
      m.f.push_back({f[0] - 1, f[1] - 1, f[2] - 1});
    }
  }
  return m;
}

TEST(Mesh, ObjOfAPlaneHasItsAreaAndUpwardNormals) {
  const double a = 0.4, b = -0.25, cell = 0.05;
  const int nx = 9, ny = 6;
  const ObjMesh m = read_obj(write_obj(temp_dir("obj") / "g.obj", plane(nx, ny, cell, a, b, 0.1)));
  ASSERT_EQ(m.v.size(), static_cast<std::size_t>(nx * ny));
  ASSERT_EQ(m.f.size(), static_cast<std::size_t>(2 * (nx - 1) * (ny - 1)));
  double area = 0.0;
  for (const auto& f : m.f) {
    const auto &p = m.v[f[0]], &q = m.v[f[1]], &r = m.v[f[2]];
    const double ux = q[0] - p[0], uy = q[1] - p[1], uz = q[2] - p[2];
    const double vx = r[0] - p[0], vy = r[1] - p[1], vz = r[2] - p[2];
    const double nx_ = uy * vz - uz * vy, ny_ = uz * vx - ux * vz, nz = ux * vy - uy * vx;
    EXPECT_GT(nz, 0.0);  // counter-clockwise seen from above
    area += 0.5 * std::sqrt(nx_ * nx_ + ny_ * ny_ + nz * nz);
  }
  const double expected = std::sqrt(1 + a * a + b * b) * (nx - 1) * cell * (ny - 1) * cell;
  EXPECT_NEAR(area, expected, 1e-6 * expected);
}

TEST(Mesh, NanVertexDropsTheSixTrianglesAroundIt) {
  HeightGrid g = plane(5, 5, 0.1, 0, 0, 0);
  g.at(2, 2) = std::nan("");
  const ObjMesh m = read_obj(write_obj(temp_dir("nan") / "g.obj", g));
  EXPECT_EQ(m.f.size(), static_cast<std::size_t>(2 * 4 * 4 - 6));
}

TEST(Mesh, SimplifiedObjKeepsEveryColumnWithinTheBoundWithFewerTriangles) {
  // A bump on a tilted plane: far from it the plane needs two triangles, near it detail.
  const int n = 41;
  HeightGrid g = plane(n, n, 0.05, 0.2, -0.1, 0.0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double dx = g.x(i) - 0.5, dy = g.y(j) - 1.0;
      g.at(i, j) += 0.05 * std::exp(-(dx * dx + dy * dy) / 0.02);
    }
  const double bound = 0.002;
  const ObjMesh m = read_obj(write_obj(temp_dir("lod") / "g.obj", g, {.simplified = true, .max_error = bound}));
  EXPECT_LT(m.f.size(), static_cast<std::size_t>(2 * (n - 1) * (n - 1)) / 4);
  ASSERT_EQ(m.vn.size(), m.v.size());
  // Every column: locate it in the triangles (seen from above) and compare heights.
  std::vector<double> worst(static_cast<std::size_t>(n * n), -1.0);
  for (const auto& f : m.f) {
    const auto &a = m.v[f[0]], &b = m.v[f[1]], &c = m.v[f[2]];
    const double area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    ASSERT_GT(area, 0.0) << "counter-clockwise seen from above";
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = g.x(i), y = g.y(j);
        const double wa = ((b[0] - x) * (c[1] - y) - (b[1] - y) * (c[0] - x)) / area;
        const double wb = ((c[0] - x) * (a[1] - y) - (c[1] - y) * (a[0] - x)) / area;
        const double wc = 1.0 - wa - wb;
        if (wa < -1e-9 || wb < -1e-9 || wc < -1e-9) continue;
        double& w = worst[static_cast<std::size_t>(j * n + i)];
        w = std::max(w, std::abs(g.at(i, j) - (wa * a[2] + wb * b[2] + wc * c[2])));
      }
  }
  for (double w : worst) {
    EXPECT_GE(w, 0.0) << "a column outside every triangle";
    EXPECT_LE(w, bound + 1e-6);  // the file's 9 digits
  }
  for (const auto& v : m.vn) {
    EXPECT_NEAR(v[0] * v[0] + v[1] * v[1] + v[2] * v[2], 1.0, 1e-6);
    EXPECT_GT(v[2], 0.0);
  }
  EXPECT_THROW(write_obj(temp_dir("lod") / "bad.obj", g, {.simplified = true, .max_error = -1.0}),
               shore::InvalidSetting);
}

TEST(Mesh, SimplifiedPlyOfAPlaneIsTwoTrianglesWithNormals) {
  const fs::path p = write_ply(temp_dir("lodply") / "g.ply", plane(17, 17, 0.1, 0.1, 0.2, 0.0), {.simplified = true});
  std::ifstream in(p, std::ios::binary);
  std::string line, header;
  while (std::getline(in, line)) {
    header += line + "\n";
    if (line == "end_header") break;
  }
  EXPECT_NE(header.find("element vertex 4"), std::string::npos) << header;
  EXPECT_NE(header.find("property float nx"), std::string::npos);
  EXPECT_NE(header.find("element face 2"), std::string::npos) << header;
  EXPECT_EQ(fs::file_size(p), header.size() + 4u * 24u + 2u * 13u);
}

TEST(Mesh, PlyHeaderCountsMatchItsBinaryBody) {
  const int nx = 4, ny = 3;
  const fs::path p = write_ply(temp_dir("ply") / "g.ply", plane(nx, ny, 0.1, 0.1, 0.2, 0.0));
  std::ifstream in(p, std::ios::binary);
  std::string line, header;
  while (std::getline(in, line)) {
    header += line + "\n";
    if (line == "end_header") break;
  }
  EXPECT_NE(header.find("element vertex 12"), std::string::npos);
  EXPECT_NE(header.find("element face 12"), std::string::npos);
  EXPECT_EQ(fs::file_size(p), header.size() + 12u * 12u + 12u * 13u);
}

TEST(Picture, FramesAndFilmstripsHaveTheirSizeAndTheColourBarItsColours) {
  const Image a(200, 100, Rgb{10, 20, 30}), b(150, 120, Rgb{40, 50, 60});
  const Legend legend = deformation_legend(0.004);
  EXPECT_EQ(legend.low, "-4.0 mm lowered");
  EXPECT_EQ(legend.high, "raised +4.0 mm");
  const Image framed = framed_picture(a, "title", &legend);
  EXPECT_EQ(framed.width(), 480);             // at least 480 wide with a colour bar
  EXPECT_EQ(framed.height(), 24 + 100 + 40);  // title strip, picture, colour bar
  EXPECT_EQ(framed.at(100, 24 + 50), (Rgb{10, 20, 30}));
  const int bar_y = 24 + 100 + 6 + 5;
  int end = 6;  // the bar runs from x = 6 to its last non-white pixel, at least 256 long
  while (end + 1 < framed.width() && !(framed.at(end + 1, bar_y) == Rgb{255, 255, 255})) ++end;
  EXPECT_GE(end - 6 + 1, 256);
  EXPECT_EQ(framed.at(6, bar_y), diverging_colour(-1.0));
  EXPECT_EQ(framed.at(end, bar_y), diverging_colour(1.0));
  const Image strip = filmstrip({a, b}, {"0 s", "1 s"}, 2);
  EXPECT_EQ(strip.width(), 2 * (200 + 8) + 8);  // two cells as wide as the widest frame, gaps of 8
  EXPECT_EQ(strip.height(), 120 + 22 + 2 * 8);  // as tall as the tallest, a label strip of 22
  EXPECT_THROW((void)filmstrip({}, {}, 3), shore::InvalidSetting);
}

TEST(RigidGround, HeightMatchesBulletsTrianglesUnderARay) {
  shore::bullet::HeightfieldTileSettings s;
  s.columns = 9;
  s.cell = 0.1;
  s.origin_x = -0.4;
  s.origin_y = -0.4;
  World w;
  RigidGround ground(w, s, [](double x, double y) { return 0.2 * std::sin(7 * x) * std::cos(5 * y) + 0.05 * x; });
  w.world().updateAabbs();
  for (double x : {-0.33, -0.07, 0.012, 0.25})
    for (double y : {-0.31, 0.04, 0.17, 0.33}) {
      const btVector3 from(btScalar(x), btScalar(y), btScalar(0.9)), to(btScalar(x), btScalar(y), btScalar(-0.9));
      btCollisionWorld::ClosestRayResultCallback hit(from, to);
      w.world().rayTest(from, to, hit);
      ASSERT_TRUE(hit.hasHit());
      EXPECT_NEAR(ground.height_at(x, y), hit.m_hitPointWorld.z(), 1e-5) << x << ", " << y;
    }
}

TEST(SceneOptions, ValidateRejectsOutOfRangeSettings) {
  SceneOptions o;
  EXPECT_NO_THROW(o.validate());
  auto bad = [](auto change) {
    SceneOptions x;
    change(x);
    EXPECT_THROW(x.validate(), shore::InvalidSetting);
  };
  bad([](SceneOptions& x) { x.threads = 0; });
  bad([](SceneOptions& x) { x.seconds = -1; });
  bad([](SceneOptions& x) { x.substep = std::nan(""); });
  bad([](SceneOptions& x) { x.cell = 0; });
  bad([](SceneOptions& x) { x.material = "gravel"; });
}

TEST(SceneOptions, OverridesReplaceDefaultsAndSmokeUsesSmokeSeconds) {
  SceneType s;
  s.name = "x";
  s.defaults = {.seconds = 3, .substep = 0.01, .material = "mud", .cell = 0.02, .smoke_seconds = 0.5};
  Overrides o;
  o.out_root = "root";
  o.threads = 2;
  SceneOptions r = resolve(s, o);
  EXPECT_EQ(r.seconds, 3);
  EXPECT_EQ(r.material, "mud");
  EXPECT_EQ(r.out_dir, fs::path("root") / "x");
  EXPECT_EQ(r.substeps(), 300);
  o.smoke = true;
  o.material = "snow";
  r = resolve(s, o);
  EXPECT_EQ(r.seconds, 0.5);
  EXPECT_EQ(r.material, "snow");
}

TEST(Report, ListsEachSceneFolderWithPicturesAndExplainedMetrics) {
  const fs::path root = temp_dir("report");
  fs::create_directories(root / "some_scene");
  std::ofstream(root / "some_scene" / "metrics.json")
      << nlohmann::json{{"scene", "some_scene"}, {"nan_count", 0}, {"files", {"a.png", "metrics.json"}}}.dump();
  std::ifstream in(write_report(root));
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  EXPECT_NE(text.find("## some_scene"), std::string::npos);
  EXPECT_NE(text.find("](some_scene/a.png)"), std::string::npos);
  EXPECT_NE(text.find("| nan_count | 0 | non-finite"), std::string::npos);
}

}  // namespace
