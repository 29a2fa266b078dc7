#pragma once
// Pixel statistics the renderer's tests read pictures by: colour distances, how many
// distinct colours a picture holds (a blank one has 1), where a colour bar ends; and a
// scene after some substeps of its smoke run.

#include <cmath>
#include <memory>
#include <vector>

#include "shore/scenes/image.h"
#include "shore/scenes/runner.h"
#include "shore/scenes/scene.h"

namespace shore::test {

inline int colour_distance(scenes::Rgb a, scenes::Rgb b) {
  return std::abs(a.r - b.r) + std::abs(a.g - b.g) + std::abs(a.b - b.b);
}

/// Distinct colours (coarsely binned) among the rows [y0, y1).
inline int distinct_colours(const scenes::Image& im, int y0, int y1) {
  std::vector<bool> seen(4096, false);
  int n = 0;
  for (int y = std::max(y0, 0); y < std::min(y1, im.height()); ++y)
    for (int x = 0; x < im.width(); ++x) {
      const scenes::Rgb c = im.at(x, y);
      const int bin = (c.r >> 4) << 8 | (c.g >> 4) << 4 | (c.b >> 4);
      if (!seen[bin]) ++n;
      seen[bin] = true;
    }
  return n;
}

/// The last pixel of row y from x = 6 (where framed_picture starts its colour bar) on that
/// is not white.
inline int colour_bar_end(const scenes::Image& im, int y) {
  int end = 6;
  while (end + 1 < im.width() && !(im.at(end + 1, y) == scenes::Rgb{255, 255, 255})) ++end;
  return end;
}

/// The scene, set up with its smoke settings, after `substeps` substeps.
inline std::unique_ptr<scenes::Scene> smoke_scene(const char* name, int substeps) {
  const scenes::SceneType& type = *scenes::find_scene(name);
  scenes::Overrides o;
  o.smoke = true;
  o.write_files = false;
  auto scene = type.create(scenes::resolve(type, o));
  for (int k = 0; k < substeps; ++k) scene->step();
  return scene;
}

}  // namespace shore::test
