#include "shore/render/picture.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "shore/core/error.h"
#include "shore/render/headless.h"
#include "shore/render/painter.h"
#include "shore/scenes/picture.h"

namespace shore::render {
namespace {

/// One headless context and renderer per process, made on first use.
struct Headless {
  HeadlessContext context;
  Renderer renderer;
};
Headless& headless() {
  static const std::unique_ptr<Headless> h = std::make_unique<Headless>();
  h->context.make_current();
  return *h;
}

scenes::Legend legend_of(const RenderSettings& s, const FrameStats& stats, bool soils) {
  if (soils) {
    if (s.ground == GroundColour::sinkage)
      return {scenes::Legend::Map::diverging, "pressed " + scenes::format_length(stats.ground_scale, false), "0",
              "loose " + scenes::format_length(stats.ground_scale, false)};
    return scenes::deformation_legend(stats.ground_scale);
  }
  if (s.water == WaterColour::velocity)
    return {scenes::Legend::Map::diverging, "down", "0", "up " + std::to_string(stats.water_scale) + " m/s"};
  return {scenes::Legend::Map::water, scenes::format_length(-stats.water_scale, true) + " trough", "",
          "crest " + scenes::format_length(stats.water_scale, true)};
}

}  // namespace

RenderSettings picture_settings(const scenes::SceneContents& contents) {
  RenderSettings s;
  s.ground = GroundColour::deformation;
  s.water = contents.soils.empty() ? WaterColour::height : WaterColour::natural;
  return s;
}

scenes::Image contents_picture(Renderer& renderer, const scenes::SceneContents& contents, const OrbitCamera& camera,
                               const PictureOptions& options) {
  const RenderSettings s = options.settings.value_or(picture_settings(contents));
  renderer.draw(camera, std::max(options.width, 16), std::max(options.height, 16), s);
  const scenes::Image picture = renderer.read_image();
  if (!options.legend) return scenes::framed_picture(picture, options.title, nullptr);
  const scenes::Legend legend = legend_of(s, renderer.stats(), !contents.soils.empty());
  return scenes::framed_picture(picture, options.title, &legend);
}

scenes::Image scene_picture(scenes::Scene& scene, const PictureOptions& options) {
  const scenes::SceneContents contents = scene.contents();
  if (contents.world == nullptr || contents.bounds.empty())
    throw std::invalid_argument("render::scene_picture: the scene has no contents to draw");
  Headless& h = headless();
  h.renderer.set_contents(contents);
  const OrbitCamera camera = options.camera.value_or(
      OrbitCamera::framing(contents.bounds, 0.0, double(std::max(options.width, 16)) / std::max(options.height, 16)));
  scenes::Image out = contents_picture(h.renderer, contents, camera, options);
  h.renderer.clear();  // the scene may go now
  return out;
}

namespace {

RenderSettings view_settings(const scenes::SceneContents& contents, const scenes::View& v) {
  RenderSettings s = picture_settings(contents);
  s.ground = static_cast<GroundColour>(static_cast<int>(v.ground));
  if (v.water != scenes::View::Water::automatic) s.water = static_cast<WaterColour>(static_cast<int>(v.water) - 1);
  s.ground_scale = v.colour_scale;
  s.water_scale = v.colour_scale;
  s.mesh_edges = v.mesh_edges;
  s.bodies = v.bodies;
  return s;
}

}  // namespace

OrbitCamera view_camera(const scenes::View& v, const scenes::Bounds& region, double aspect) {
  OrbitCamera c;
  if (v.camera == scenes::View::Camera::top) {
    c.pitch_deg = 89.5;  // straight down, north up; a narrow lens is nearly orthographic
    c.yaw_deg = -90.0;
    c.fov_deg = 8.0;
  } else {
    c.pitch_deg = v.elevation_deg;
    c.yaw_deg = v.azimuth_deg;
  }
  c.frame(region, v.target_z, aspect);
  return c;
}

scenes::Bounds view_region(const scenes::SceneContents& contents, const scenes::View& v) {
  return v.region.empty() ? contents.bounds : v.region;
}

int view_height(const scenes::View& v, const scenes::Bounds& region) {
  if (v.height > 0) return v.height;
  if (v.camera != scenes::View::Camera::top) return v.width * 9 / 16;
  const double aspect = (region.y1 - region.y0) / (region.x1 - region.x0);
  return std::clamp(static_cast<int>(std::lround(v.width * aspect)), 16, 2 * v.width);
}

namespace {}  // namespace

void spray_lines(const scenes::SceneContents& contents, const scenes::Bounds& r, double least, LineBatch& out) {
  const btVector3 ink(0.10f, 0.08f, 0.06f);
  for (const scenes::SoilContents& s : contents.soils)
    for (const terrain::SprayParticle& p : s.soil->spray_particles()) {
      if (p.position.x < r.x0 || p.position.x > r.x1 || p.position.y < r.y0 || p.position.y > r.y1 ||
          !s.region.contains(p.position.x, p.position.y))
        continue;
      const auto h = btScalar(0.5 * std::max(2.0 * p.radius, least));
      const btVector3 c(btScalar(p.position.x), btScalar(p.position.y), btScalar(p.position.z));
      out.drawLine(c - btVector3(h, 0, 0), c + btVector3(h, 0, 0), ink);
      out.drawLine(c - btVector3(0, h, 0), c + btVector3(0, h, 0), ink);
      out.drawLine(c - btVector3(0, 0, h), c + btVector3(0, 0, h), ink);
    }
}

HeadlessPainter::HeadlessPainter() { (void)headless(); }

std::string HeadlessPainter::description() const { return headless().context.description(); }

scenes::Image HeadlessPainter::paint(const scenes::SceneContents& contents, const scenes::View& v) {
  const Check c{"scenes.View"};
  c.in_closed("width", v.width, 16, 8192);
  c.in_closed("height", v.height, 0, 8192);
  c.in_closed("elevation_deg", v.elevation_deg, 5.0, 85.0);
  c.non_negative("colour_scale", v.colour_scale);
  if (contents.world == nullptr || contents.bounds.empty())
    throw std::invalid_argument("render::HeadlessPainter: the scene has no contents to draw");
  const scenes::Bounds region = view_region(contents, v);
  const double rx = region.x1 - region.x0, ry = region.y1 - region.y0;
  const int height = view_height(v, region);
  Headless& h = headless();
  h.renderer.set_contents(contents);
  const OrbitCamera camera = view_camera(v, region, double(v.width) / height);
  const RenderSettings s = view_settings(contents, v);
  LineBatch lines;
  if (v.spray) spray_lines(contents, region, 1.5 * std::max(rx, ry) / v.width, lines);
  h.renderer.draw(camera, v.width, height, s, &lines);
  const scenes::Image picture = h.renderer.read_image();
  const FrameStats& stats = h.renderer.stats();
  std::string title = v.title;
  if (v.mesh_edges && !title.empty())
    title += ": " + std::to_string(stats.surface_triangles) + " triangles drawn (" +
             std::to_string(stats.full_triangles) + " in full)";
  const bool coloured = !contents.soils.empty() || !contents.waters.empty();
  scenes::Image out = [&] {
    if (!v.legend || !coloured) return scenes::framed_picture(picture, title, nullptr);
    const scenes::Legend legend = legend_of(s, stats, !contents.soils.empty() && s.ground != GroundColour::natural);
    return scenes::framed_picture(picture, title, &legend);
  }();
  h.renderer.clear();  // the scene may go now
  return out;
}

}  // namespace shore::render
