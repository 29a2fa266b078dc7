#include "gl_pictures.h"

#include <cstdio>

#ifdef SHORE_DEMO_GL
#include "shore/render/headless.h"
#include "shore/render/picture.h"
#endif

namespace shore::demo {

scenes::DrawHook gl_pictures(bool enabled) {
#ifdef SHORE_DEMO_GL
  if (!enabled) return {};
  return [](scenes::Scene& scene, scenes::Drawing& out) {
    static bool unavailable = false;
    if (unavailable || scene.contents().world == nullptr) return;
    try {
      render::PictureOptions o;
      o.title = scene.contents().soils.empty() ? "3-D view (OpenGL), water coloured by height"
                                               : "3-D view (OpenGL), ground coloured by deformation";
      out.png("render.png", render::scene_picture(scene, o));
    } catch (const render::ContextError& e) {
      unavailable = true;
      std::fprintf(stderr, "shore-demo: no OpenGL pictures (%s); the software pictures are written\n", e.what());
    }
  };
#else
  (void)enabled;
  return {};
#endif
}

}  // namespace shore::demo
