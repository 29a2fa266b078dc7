#pragma once
// shore-demo's pictures: the OpenGL renderer's painter (shore_render, headless through EGL
// on Mesa), when the renderer is built.

#include <memory>

#include "shore/scenes/picture.h"

namespace shore::demo {

/// The painter every scene's pictures come from. Null if `enabled` is false (--no-pictures)
/// or shore-demo was built without the renderer; both are said once on stderr. Throws
/// std::runtime_error with what failed and how to go on if the renderer is built but no
/// headless OpenGL 3.3 context can be made.
std::unique_ptr<scenes::Painter> make_painter(bool enabled);

}  // namespace shore::demo
