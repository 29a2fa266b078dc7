#pragma once
// Water surfaces as the water scenes' meshes and metrics see them: copied into a
// HeightGrid, and wave heights. (The level a floater sits in is water::Surface::level_around.)

#include "shore/scenes/height_grid.h"
#include "shore/water/surface.h"

namespace shore::scenes {

/// Node heights of the surface (node (i, j) at its rest position), m.
HeightGrid surface_grid(const water::Surface& surface);

/// Largest |height - rest level| over the surface's nodes that are not fixed, m.
double max_deviation(const water::Surface& surface);

}  // namespace shore::scenes
