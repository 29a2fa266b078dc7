#pragma once
// Internal: buoyancy and drag of one body from its submerged parts (buoyancy.h has the
// model), clamped for one substep.

#include <LinearMath/btMatrix3x3.h>

#include "shore/bullet/buoyancy.h"
#include "water_shape.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace water_detail {

/// The body's state the drag needs.
struct Motion {
  Vec3 com;                 ///< centre of mass, world
  Vec3 v;                   ///< linear velocity
  Vec3 w;                   ///< angular velocity
  double mass = 0.0;        ///< kg; 0 (and not articulated): kinematic or static (the forces are reported, not limited)
  btMatrix3x3 inv_inertia;  ///< world inverse inertia tensor
  /// A body whose mass and inertia cannot be taken apart: a btMultiBody link (a push at its
  /// centre turns it through its joints, a twist moves it) or a rigid body Bullet holds to
  /// some axes (CoupledBody::mobility gives their 6 x 6 mobility at the centre). Its drag is
  /// limited through the mobility instead of mass and inv_inertia.
  bool articulated = false;
  double mobility[6][6] = {};
};

/// Forces on the body from `wet` (its analytic parts) and `sampled_volume` /
/// `sampled_moment` (its sampled parts) under water plane w, over a substep h: drag scaled
/// down where it would reverse the relative velocity or spin within the substep. For an
/// articulated body, down to where the drag impulse would reverse its relative motion along
/// that impulse (6-D, through its mobility): the drag then never adds kinetic energy to the
/// multibody however light the link is in some direction.
BodyWater water_forces(const Submerged& wet, double sampled_volume, Vec3 sampled_moment, const WaterPlane& w,
                       const FluidSettings& fluid, const Motion& m, double h);

}  // namespace water_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
