#pragma once
// Helpers shared by the water scenes (pond, beach): copying a water surface into a
// HeightGrid, counting non-finite state, hashing bodies, and water pictures with land and
// floating bodies painted over the surface.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <BulletDynamics/Dynamics/btRigidBody.h>

#include "shore/core/hash.h"
#include "shore/demo/height_grid.h"
#include "shore/demo/image.h"
#include "shore/water/surface.h"

namespace shore::demo::water_scene {

/// Node heights of the surface (node (i, j) at its rest position), m.
HeightGrid surface_grid(const water::Surface& surface);

/// Non-finite node heights of the surface.
long non_finite_heights(const water::Surface& surface);
/// Non-finite values in a body's position, orientation and velocities.
long non_finite_state(const btRigidBody& body);

/// Adds a body's position, orientation and velocities to a hash.
void hash_body(StateHash& hash, const btRigidBody& body);

/// Upper and lower envelopes (nominal solids) of the bodies over the columns of `like`
/// (NaN where no body), for pictures.
struct BodyEnvelopes {
  HeightGrid top;
  HeightGrid bottom;
};
BodyEnvelopes body_envelopes(const std::vector<const btRigidBody*>& bodies, const HeightGrid& like);

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

/// Mean water height on a circle of `radius` around (x, y) (32 points, bilinear): the level
/// a floater at (x, y) sits in, free of the surface under the body itself, which the body's
/// displacement raises.
double level_around(const water::Surface& surface, double x, double y, double radius);

/// "t = 1.25 s".
std::string time_label(double seconds);

}  // namespace shore::demo::water_scene
