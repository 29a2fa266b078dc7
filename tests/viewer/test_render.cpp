// The OpenGL renderer headless (EGL on Mesa): pictures of real scenes checked for size,
// for not being blank, for the colour bar, the soil meshes for uploading only the chunks that changed and for
// culling the chunks outside the view.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "picture_checks.h"
#include "shore/render/headless.h"
#include "shore/render/picture.h"
#include "shore/render/renderer.h"
#include "shore/render/shape_mesh.h"
#include "shore/scenes/image.h"
#include "shore/scenes/runner.h"
#include "shore/scenes/scene.h"

#include <btBulletDynamicsCommon.h>

namespace {

using shore::scenes::Image;
using shore::scenes::Rgb;

using shore::test::colour_distance;
using shore::test::distinct_colours;
using shore::test::smoke_scene;

/// The vehicle scene after `substeps`, drawn by a renderer of its own headless context.
struct VehicleRenderer {
  explicit VehicleRenderer(int substeps = 0) : scene(smoke_scene("vehicle", substeps)) { r.set_contents(c); }
  std::unique_ptr<shore::scenes::Scene> scene;
  shore::render::HeadlessContext context;
  shore::render::Renderer r;
  shore::scenes::SceneContents c = scene->contents();
  ~VehicleRenderer() { r.clear(); }
};

TEST(RenderHeadless, VehiclePictureHasItsSizeContentAndColourBar) {
  auto scene = smoke_scene("vehicle", 120);
  shore::render::PictureOptions o;
  o.width = 640;
  o.height = 360;
  o.title = "vehicle";
  const Image im = shore::render::scene_picture(*scene, o);
  // 24 px title strip above, 40 px colour bar below (framed_picture).
  ASSERT_EQ(im.width(), 640);
  ASSERT_EQ(im.height(), 360 + 24 + 40);
  EXPECT_GT(distinct_colours(im, 24, 24 + 360), 40) << "the 3-D view is (nearly) blank";
  // The colour bar: its left end is the diverging map's "lowered" end, its right end "raised".
  const int bar_y = 24 + 360 + 6 + 5;
  const int end = shore::test::colour_bar_end(im, bar_y);
  EXPECT_GE(end - 6 + 1, 256) << "the colour bar is at least 256 pixels long";
  EXPECT_LT(colour_distance(im.at(6, bar_y), shore::scenes::diverging_colour(-1.0)), 12);
  EXPECT_LT(colour_distance(im.at(end, bar_y), shore::scenes::diverging_colour(1.0)), 12);
  EXPECT_LT(colour_distance(im.at((6 + end) / 2, bar_y), shore::scenes::diverging_colour(0.0)), 12);
}

TEST(RenderHeadless, PondPictureShowsWaterWithTheWaterColourBar) {
  auto scene = smoke_scene("pond", 60);
  shore::render::PictureOptions o;
  o.width = 480;
  o.height = 320;
  const Image im = shore::render::scene_picture(*scene, o);
  ASSERT_EQ(im.height(), 320 + 40);
  EXPECT_GT(distinct_colours(im, 0, 320), 40);
  const int bar_y = 320 + 6 + 5;
  EXPECT_LT(colour_distance(im.at(7, bar_y), shore::scenes::water_colour(-1.0)), 12);
}

TEST(RenderHeadless, SoilMeshUploadsOnlyTheChangedChunks) {
  VehicleRenderer v;
  auto& [scene, context, r, c] = v;
  const shore::render::OrbitCamera camera = shore::render::OrbitCamera::framing(c.bounds);
  const shore::render::RenderSettings settings = shore::render::picture_settings(c);
  r.draw(camera, 640, 360, settings);
  const auto whole = r.stats().whole_soil_bytes;
  const auto first = r.stats().soil_bytes;
  EXPECT_GT(first, 0) << "the first frame uploads the meshes";
  EXPECT_LT(first, whole) << "a simplified mesh is smaller than the full-resolution one";
  EXPECT_LT(r.stats().surface_triangles, r.stats().full_triangles);
  r.draw(camera, 640, 360, settings);
  EXPECT_EQ(r.stats().soil_bytes, 0) << "nothing changed, the camera did not move: nothing uploaded";
  std::int64_t most = 0, total = 0;
  for (int frame = 0; frame < 30; ++frame) {
    for (int k = 0; k < 4; ++k) scene->step();
    r.draw(camera, 640, 360, settings);
    most = std::max(most, r.stats().soil_bytes);
    total += r.stats().soil_bytes;
  }
  EXPECT_GT(total, 0) << "the wheels on the sand change chunks";
  EXPECT_LT(most, whole / 4) << "a frame uploads a small part of the field";
  r.clear();
}

// After the smoke run: the wheels' ruts along the one soil (sand, then mud) make its mesh
// several chunks.
TEST(RenderHeadless, ChunksOutsideTheViewAreCulled) {
  VehicleRenderer v(240);
  auto& [scene, context, r, c] = v;
  shore::render::RenderSettings settings = shore::render::picture_settings(c);
  settings.shadows = false;
  shore::render::OrbitCamera wide = shore::render::OrbitCamera::framing(c.bounds);
  r.draw(wide, 320, 180, settings);
  EXPECT_EQ(r.stats().chunks_culled, 0) << "the framing view sees the whole scene";
  // Close to the sand's near end, looking away from the rest of the field: most chunks are behind.
  shore::render::OrbitCamera near = wide;
  near.target = {std::max(c.soils.front().region.x0, c.bounds.x0) + 0.3, 0.0, 0.0};  // the sand's near end
  near.yaw_deg = 0.0;  // the eye on the +x side of the target, looking towards -x: the rest is behind it
  near.distance = 0.6;
  near.pitch_deg = 20.0;
  r.draw(near, 320, 180, settings);
  EXPECT_GT(r.stats().chunks_culled, 0);
  EXPECT_GT(r.stats().chunks_drawn, 0);
  EXPECT_LT(r.stats().chunks_drawn, r.stats().surface_chunks);
  r.clear();
}

TEST(ShapeMesh, ClosedShapesEncloseTheirVolume) {
  // The divergence theorem over the triangles: sum of (a . (b x c)) / 6 is the enclosed
  // volume, for outward-wound faces.
  auto volume = [](const shore::render::ShapeMesh& m) {
    double v = 0;
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
      auto p = [&](std::size_t k) {
        const std::uint32_t i = m.indices[t + k];
        return btVector3(m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]);
      };
      v += double(p(0).dot(p(1).cross(p(2)))) / 6.0;
    }
    return v;
  };
  const double pi = 3.14159265358979;
  EXPECT_NEAR(volume(shore::render::shape_mesh(btBoxShape(btVector3(0.1f, 0.2f, 0.3f)))), 8 * 0.006, 1e-6);
  EXPECT_NEAR(volume(shore::render::shape_mesh(btSphereShape(0.5f), 64)), 4.0 / 3.0 * pi * 0.125, 0.01 * 0.52);
  EXPECT_NEAR(volume(shore::render::shape_mesh(btCylinderShapeZ(btVector3(0.2f, 0.2f, 0.5f)), 64)), pi * 0.04 * 1.0,
              0.01 * 0.126);
  EXPECT_NEAR(volume(shore::render::shape_mesh(btConeShapeZ(0.3f, 0.6f), 64)), pi * 0.09 * 0.6 / 3.0, 0.01 * 0.057);
}

}  // namespace
