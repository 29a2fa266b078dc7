#pragma once
// The scenes' painter (shore/scenes/picture.h) on the OpenGL renderer, headless (EGL on
// Mesa's surfaceless platform, llvmpipe without a GPU): every picture shore-demo writes.
//
//   shore::render::HeadlessPainter painter;   // throws ContextError without a working EGL
//   shore::scenes::run_scene(type, options, progress, &painter);

#include <string>

#include "shore/render/camera.h"
#include "shore/render/line_batch.h"
#include "shore/scenes/picture.h"

namespace shore::render {

/// The camera a view of `region` uses in a picture of this aspect (width / height).
OrbitCamera view_camera(const scenes::View& view, const scenes::Bounds& region, double aspect);
/// The region a view frames (its own, or the contents' bounds) and its 3-D view's height in pixels.
scenes::Bounds view_region(const scenes::SceneContents& contents, const scenes::View& view);
int view_height(const scenes::View& view, const scenes::Bounds& region);
/// The soils' spray particles in flight inside the region as three short dark lines each
/// (at least `least` metres long, so millimetre grains show on a wide picture).
void spray_lines(const scenes::SceneContents& contents, const scenes::Bounds& region, double least, LineBatch& out);

class HeadlessPainter final : public scenes::Painter {
 public:
  /// Makes the process's headless context (picture.h) now, so a missing EGL is reported
  /// before a scene runs. Throws ContextError naming the step that failed.
  HeadlessPainter();
  /// The view of the contents: soils and water as simplified meshes at 1 pixel, the bodies,
  /// the soils' spray particles as dark crosses, framed with the title and the colour bar.
  scenes::Image paint(const scenes::SceneContents& contents, const scenes::View& view) override;
  /// "OpenGL 4.5 (Core Profile) Mesa ... | llvmpipe ...".
  [[nodiscard]] std::string description() const;
};

}  // namespace shore::render
