#pragma once
// shore-demo's pictures from the OpenGL renderer (shore_render, headless through EGL):
// render.png in every scene's folder, when the renderer is built; the software pictures
// stay beside them (and are all there is without it or without a working EGL).

#include "shore/scenes/runner.h"

namespace shore::demo {

/// The hook run_scene calls after each scene's own pictures; empty if the renderer is not
/// built or `enabled` is false. A missing EGL is reported once on stderr, then skipped.
scenes::DrawHook gl_pictures(bool enabled);

}  // namespace shore::demo
