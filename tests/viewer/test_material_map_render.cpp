// A painted soil in the natural ground colours: each column in its palette entry's colour,
// the same pixels as a soil of that material alone; a soil that never painted drawn as
// before maps (no texture), whatever its palette; colours settable by material name.
#include <gtest/gtest.h>

#include <Eigen/Core>

#include "picture_checks.h"
#include "shore/render/headless.h"
#include "shore/render/renderer.h"
#include "shore/scenes/image.h"
#include "shore/terrain/terrain.h"

namespace {

using shore::scenes::Image;
using shore::scenes::Rgb;
using shore::terrain::Material;
using shore::terrain::Terrain;

constexpr int kPixels = 160;

Terrain flat(const Material& m) {
  shore::terrain::TerrainSettings s;
  s.cell = 0.02;
  s.tile_columns = 16;
  s.threads = 1;
  s.material = m;
  return Terrain(s);
}

/// A 1 m square of the soil from straight above, natural colours, no shadows or sky.
struct TopView {
  shore::render::HeadlessContext context;
  shore::render::Renderer r;
  explicit TopView(Terrain& soil) {
    shore::scenes::SceneContents c;
    c.soils = {{&soil, nullptr, {0.0, 0.0, 1.0, 1.0}}};
    c.bounds = {0.0, 0.0, 1.0, 1.0};
    r.set_contents(c);
  }
  ~TopView() { r.clear(); }
  Image draw(const shore::render::RenderSettings& extra = {}) {
    shore::render::OrbitCamera camera;
    camera.target = {0.5, 0.5, 0.0};
    camera.yaw_deg = -90.0, camera.pitch_deg = 89.0, camera.distance = 2.5;
    shore::render::RenderSettings s = extra;
    s.ground = shore::render::GroundColour::natural;
    s.shadows = false, s.sky = false, s.bodies = false, s.samples = 1;
    r.draw(camera, kPixels, kPixels, s);
    return r.read_image();
  }
};

Image top_view(Terrain& soil, const shore::render::RenderSettings& extra = {}) { return TopView(soil).draw(extra); }

Rgb left(const Image& im) { return im.at(kPixels / 4, kPixels / 2); }
Rgb right(const Image& im) { return im.at(3 * kPixels / 4, kPixels / 2); }

bool same(const Rgb& a, const Rgb& b) { return a == b; }

bool same_pixels(const Image& a, const Image& b) {
  if (a.width() != b.width() || a.height() != b.height()) return false;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x)
      if (!(a.at(x, y) == b.at(x, y))) return false;
  return true;
}

TEST(MaterialMapRender, PaintedColumnsLookAsTheirMaterialAlone) {
  Terrain sand = flat(Material::sand()), mud = flat(Material::mud());
  const Image plain_sand = top_view(sand), plain_mud = top_view(mud);
  ASSERT_GT(shore::test::colour_distance(left(plain_sand), left(plain_mud)), 40) << "sand and mud look alike";
  // A one-entry palette, nothing painted: drawn as before maps, pixel for pixel.
  Terrain palette_only = flat(Material::sand());
  palette_only.set_palette({Material::sand()});
  const Image unpainted = top_view(palette_only);
  EXPECT_TRUE(same_pixels(unpainted, plain_sand));
  // Mud painted over x > 0.5 m: its half looks as mud alone, the rest as sand alone.
  Terrain painted = flat(Material::sand());
  painted.set_palette({Material::sand(), Material::mud()});
  painted.paint_where(
      {-5, -5, 60, 60}, [](double x, double) { return x > 0.5; }, 1);
  const Image map = top_view(painted);
  EXPECT_TRUE(same(left(map), left(plain_sand)));
  EXPECT_TRUE(same(right(map), right(plain_mud)));
  // A colour set by name replaces the preset's.
  shore::render::RenderSettings blue;
  blue.material_colours["mud"] = Eigen::Vector3d(0.1, 0.2, 0.9);
  const Image recoloured = top_view(painted, blue);
  EXPECT_TRUE(same(left(recoloured), left(plain_sand)));
  EXPECT_GT(right(recoloured).b, right(recoloured).r + 60);
}

// The renderer follows a repaint between frames (the tiles repainted since it last looked).
TEST(MaterialMapRender, ARepaintShowsInTheNextFrame) {
  Terrain mud = flat(Material::mud());
  const Image plain_mud = top_view(mud);
  Terrain painted = flat(Material::sand());
  painted.set_palette({Material::sand(), Material::mud()});
  TopView view(painted);
  const Image before = view.draw();
  ASSERT_FALSE(same(left(before), left(plain_mud)));
  painted.paint_rect({0, 0, 25, 50}, 1);  // x < 0.5 m: the left half
  const Image after = view.draw();
  EXPECT_TRUE(same(left(after), left(plain_mud)));
  EXPECT_TRUE(same(right(after), right(before)));
  painted.paint_rect({25, 0, 25, 50}, 1);  // and the right half, into the texture made above
  EXPECT_TRUE(same(right(view.draw()), right(plain_mud)));
}

}  // namespace
