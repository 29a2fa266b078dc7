// Every scene's pictures, as shore-demo writes them, come from the OpenGL renderer: run
// each scene's smoke run with the headless painter and check each PNG for its size, for
// not being blank and for its colour bar; the soil's deformation is where the bodies
// pressed it, and the bodies are drawn where they are.
#include <gtest/gtest.h>

#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "picture_checks.h"
#include "shore/render/painter.h"
#include "shore/scenes/image.h"
#include "shore/scenes/runner.h"
#include "shore/scenes/scene.h"
#include "shore/scenes/world.h"

#include <btBulletDynamicsCommon.h>

namespace fs = std::filesystem;
using shore::scenes::Image;
using shore::scenes::Rgb;

namespace {

Image read_png(const fs::path& p) {
  int w = 0, h = 0, n = 0;
  unsigned char* data = stbi_load(p.c_str(), &w, &h, &n, 3);
  if (data == nullptr) return {};
  Image im(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const unsigned char* c = data + 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + x);
      im.at(x, y) = {c[0], c[1], c[2]};
    }
  stbi_image_free(data);
  return im;
}

using shore::test::colour_distance;
using shore::test::distinct_colours;

/// True if the bottom 40 rows hold a colour bar: a row that from x = 6 runs at least 256
/// pixels, from the low end of the diverging or the water map to its high end.
bool has_colour_bar(const Image& im) {
  for (int y = std::max(im.height() - 40, 0); y < im.height(); ++y) {
    const int end = shore::test::colour_bar_end(im, y);
    if (end - 6 + 1 < 256) continue;
    const Rgb lo = im.at(6, y), hi = im.at(end, y);
    if (colour_distance(lo, shore::scenes::diverging_colour(-1.0)) < 12 &&
        colour_distance(hi, shore::scenes::diverging_colour(1.0)) < 12)
      return true;
    if (colour_distance(lo, shore::scenes::water_colour(-1.0)) < 12 &&
        colour_distance(hi, shore::scenes::water_colour(1.0)) < 12)
      return true;
  }
  return false;
}

shore::render::HeadlessPainter& painter() {
  static shore::render::HeadlessPainter p;
  return p;
}

class ScenePictures : public testing::TestWithParam<std::string> {};

TEST_P(ScenePictures, EveryPictureIsDrawnNotBlankAndHasItsColourBar) {
  const shore::scenes::SceneType& type = *shore::scenes::find_scene(GetParam());
  shore::scenes::Overrides o;
  o.smoke = true;
  o.threads = 1;
  o.out_root = fs::path(testing::TempDir()) / "shore_scene_pictures";
  const shore::scenes::SceneResult r =
      shore::scenes::run_scene(type, shore::scenes::resolve(type, o), shore::scenes::ProgressMode::quiet, &painter());
  EXPECT_TRUE(r.metrics["pictures_skipped"].empty()) << r.metrics["pictures_skipped"].dump();
  int pictures = 0;
  for (const fs::path& f : r.files) {
    if (f.extension() != ".png") continue;
    ++pictures;
    const Image im = read_png(f);
    ASSERT_GT(im.width(), 100) << f;
    ASSERT_GT(im.height(), 60) << f;
    EXPECT_GT(distinct_colours(im, 0, im.height() - 40), 30) << f << ": (nearly) blank";
    const std::string name = f.filename().string();
    // The vehicle's material map is drawn in the ground's natural colours: no scale to show.
    const bool bar = name != "filmstrip.png" && !(GetParam() == "pond" && name == "lod.png") &&
                     GetParam() != "rigid_drop" && name != "materials.png";
    if (bar) {
      EXPECT_TRUE(has_colour_bar(im)) << f << ": no colour bar";
    }
  }
  EXPECT_GE(pictures, 3) << "every scene draws a top or oblique view, a filmstrip and more";
}

INSTANTIATE_TEST_SUITE_P(AllScenes, ScenePictures, testing::ValuesIn(shore::scenes::scene_names()),
                         [](const testing::TestParamInfo<std::string>& p) { return p.param; });

/// Pixel (column, row) of a world point in a painted view (title strip of 24 rows above).
Eigen::Vector2d pixel_of(const shore::render::OrbitCamera& c, double aspect, int w, int h, const Eigen::Vector3d& p) {
  const Eigen::Vector4f q =
      c.projection(aspect) * c.view() * Eigen::Vector4f(float(p.x()), float(p.y()), float(p.z()), 1.0f);
  return {(q.x() / q.w() * 0.5 + 0.5) * w, (0.5 - q.y() / q.w() * 0.5) * h + 24.0};
}

TEST(ScenePictures, TheImpactTopViewShowsCratersUnderTheBodiesAndTheBodiesWhereTheyAre) {
  const shore::scenes::SceneType& type = *shore::scenes::find_scene("impact");
  shore::scenes::Overrides o;
  o.smoke = true;
  o.write_files = false;
  const shore::scenes::SceneOptions options = shore::scenes::resolve(type, o);
  auto scene = type.create(options);
  for (int k = 0; k < options.substeps(); ++k) scene->step();
  const shore::scenes::SceneContents c = scene->contents();
  shore::scenes::View v{.camera = shore::scenes::View::Camera::top, .width = 640, .title = "impact"};
  const Image with = painter().paint(c, v);
  v.bodies = false;
  const Image without = painter().paint(c, v);
  const shore::scenes::Bounds region = shore::render::view_region(c, v);
  const int h = shore::render::view_height(v, region);
  const shore::render::OrbitCamera cam = shore::render::view_camera(v, region, 640.0 / h);
  int bodies_checked = 0, lowered_under = 0;
  for (const btRigidBody* b : c.world->bodies()) {
    if (b->isStaticObject()) continue;
    const btVector3 p = b->getCenterOfMassPosition();
    if (p.x() < region.x0 || p.x() > region.x1 || p.y() < region.y0 || p.y() > region.y1) continue;
    const Eigen::Vector2d px = pixel_of(cam, 640.0 / h, 640, h, {p.x(), p.y(), p.z()});
    const int x = static_cast<int>(px.x()), y = static_cast<int>(px.y());
    if (x < 2 || y < 26 || x >= 638 || y >= 24 + h - 2) continue;
    ++bodies_checked;
    // The body is drawn there: with and without bodies differ at its centre.
    EXPECT_GT(colour_distance(with.at(x, y), without.at(x, y)), 30) << "body at " << p.x() << ", " << p.y();
    // Under it the soil is lowered: the diverging map's blue side (b > r).
    const Rgb g = without.at(x, y);
    if (g.b > g.r + 10) ++lowered_under;
  }
  EXPECT_GE(bodies_checked, 6);
  EXPECT_GE(lowered_under, bodies_checked * 2 / 3) << "craters (blue) under most bodies";
}

}  // namespace
