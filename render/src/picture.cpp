#include "shore/render/picture.h"

#include <algorithm>
#include <memory>
#include <stdexcept>

#include "shore/render/headless.h"
#include "shore/scenes/render.h"

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
  renderer.sync();
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

}  // namespace shore::render
