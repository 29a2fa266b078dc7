#pragma once
// Bodies as the pictures show them: their upper and lower surfaces over a grid's columns.

#include <span>

#include <BulletDynamics/Dynamics/btRigidBody.h>

#include "shore/scenes/height_grid.h"

namespace shore::scenes {

struct BodyEnvelopes {
  HeightGrid top;     ///< highest body point over each column of the frame (NaN: no body)
  HeightGrid bottom;  ///< lowest body point over each column (NaN: no body)
};

/// The envelopes of the bodies' nominal solids (shore::bullet's rasterizer, no collision
/// margin) over `frame`'s columns, merged. Bodies whose pose cannot be drawn (not finite)
/// are left out.
BodyEnvelopes body_envelopes(std::span<const btRigidBody* const> bodies, const HeightGrid& frame);

}  // namespace shore::scenes
