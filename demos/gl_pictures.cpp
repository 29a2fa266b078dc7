#include "gl_pictures.h"

#include <cstdio>
#include <stdexcept>
#include <string>

#ifdef SHORE_DEMO_GL
#include "shore/render/headless.h"
#include "shore/render/painter.h"
#endif

namespace shore::demo {

std::unique_ptr<scenes::Painter> make_painter(bool enabled) {
  if (!enabled) {
    std::fprintf(stderr, "shore-demo: --no-pictures: no pictures are drawn (metrics and meshes only)\n");
    return nullptr;
  }
#ifdef SHORE_DEMO_GL
  try {
    auto painter = std::make_unique<render::HeadlessPainter>();
    std::fprintf(stderr, "shore-demo: pictures from %s\n", painter->description().c_str());
    return painter;
  } catch (const render::ContextError& e) {
    throw std::runtime_error(std::string("no headless OpenGL 3.3 context for the pictures (") + e.what() +
                             "); install Mesa's EGL and llvmpipe (scripts/install-deps.sh viewer) or run with "
                             "--no-pictures");
  }
#else
  std::fprintf(stderr,
               "shore-demo: built without the OpenGL renderer (SHORE_BUILD_VIEWER found no libepoxy): no pictures "
               "are drawn; install them with scripts/install-deps.sh viewer\n");
  return nullptr;
#endif
}

}  // namespace shore::demo
