#pragma once
// Water surfaces as the water scenes' pictures and metrics see them: copied into a
// HeightGrid, drawn with land and floating bodies painted over them, and wave heights. (The
// level a floater sits in is water::Surface::level_around.)

#include <functional>
#include <string>
#include <vector>

#include <BulletDynamics/Dynamics/btRigidBody.h>

#include "shore/scenes/height_grid.h"
#include "shore/scenes/image.h"
#include "shore/water/surface.h"

namespace shore::scenes {

/// Node heights of the surface (node (i, j) at its rest position), m.
HeightGrid surface_grid(const water::Surface& surface);

/// What render_water_scene paints over the water.
struct WaterOverlay {
  /// Whether the world point (x, y) is land (island, dry sand); empty: no land.
  std::function<bool(double x, double y)> land;
  std::vector<const btRigidBody*> bodies;  ///< drawn from above, tinted and outlined
};

/// render_water of the surface, with land painted sand-coloured and bodies grey, both
/// outlined. scale: metres to full colour (0: the largest deviation over water nodes).
Image render_water_scene(const water::Surface& surface, const WaterOverlay& overlay, double scale,
                         const std::string& title, int min_pixels = 480);

/// Largest |height - rest level| over the surface's nodes that are not fixed, m.
double max_deviation(const water::Surface& surface);

}  // namespace shore::scenes
