#pragma once
// A scene's picture from the OpenGL renderer, headless (headless.h: EGL on Mesa, no
// display or GPU needed): the 3-D view of its contents, soil coloured by deformation with
// the colour bar users read millimetres from, water coloured by height where there is no
// soil, under a title.

#include <optional>
#include <string>

#include "shore/render/camera.h"
#include "shore/render/renderer.h"
#include "shore/scenes/image.h"
#include "shore/scenes/scene.h"

namespace shore::render {

struct PictureOptions {
  int width = 1280;   ///< pixels, >= 16
  int height = 720;   ///< pixels, >= 16
  std::string title;  ///< above the picture (empty: none)
  /// Ground and water colours (the defaults: deformation, and water by height in scenes
  /// without soil); the legend follows them.
  std::optional<RenderSettings> settings;
  std::optional<OrbitCamera> camera;  ///< default: framing the scene's bounds
  bool legend = true;                 ///< the colour bar under the picture
};

/// The picture of the scene as it is now. Throws ContextError if no headless OpenGL 3.3
/// context can be made, std::invalid_argument if the scene shows nothing (no contents).
scenes::Image scene_picture(scenes::Scene& scene, const PictureOptions& options = {});

/// The picture of contents drawn with an existing renderer (a current context): the
/// viewer's headless frames.
scenes::Image contents_picture(Renderer& renderer, const scenes::SceneContents& contents, const OrbitCamera& camera,
                               const PictureOptions& options);

/// The settings a picture of these contents uses by default.
RenderSettings picture_settings(const scenes::SceneContents& contents);

}  // namespace shore::render
