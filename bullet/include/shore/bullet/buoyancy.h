#pragma once
// What the water does to a floating body: buoyancy and drag, from the body's shape.
//
// Buoyancy. The water surface under the body is taken as the plane fitted (least squares)
// to the water nodes under its footprint. The part of the body below that plane is
// integrated exactly: boxes and convex hulls as polyhedra (volume and centre of buoyancy
// from the divergence theorem), balls with the spherical cap's closed forms; cylinders,
// cones and capsules as hulls of 32-sided rings scaled to their exact volume (exact when
// fully wet, within a few 0.1 % of the wet volume when cut at an angle); concave meshes by
// sampling their envelopes on a grid of `samples_per_cell` per water cell. Buoyancy
// rho g V acts upward at the centre of buoyancy, so a heeled body rights itself. Nothing
// here depends on how finely anything is sampled (but for meshes).
//
// Drag. On the relative velocity u of the centre of buoyancy (the body's velocity there
// minus the water's vertical velocity under it),
//   F = -(1/2 rho C_d A |u| + rho k A) u,
// A the area the wet part presents to the flow: the projection of the submerged solid
// along u (for a polyhedron half the sum of |A_f . u| over its closed wet surface, for a
// ball in closed form; a towed box of width b and draft d: A = b d; a sinking ball: pi r^2).
// Rotation: each wet face whose outward normal faces its own velocity relative to the
// centre of buoyancy, omega x (c_f - c_b), feels the same law on its projected area, which
// damps roll and pitch by the shape (a ball has no such faces: no pressure drag on spin).
// Drag impulses never reverse the relative velocity (or spin) within a substep.

#include <LinearMath/btVector3.h>

#include "shore/bullet/config.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

struct FluidSettings {
  double density = 1000.0;  ///< kg/m^3, water density, > 0 (the coupling takes the surface's)
  double gravity = 9.81;    ///< m/s^2, > 0
  /// C_d, dimensionless, >= 0: pressure drag 1/2 rho C_d A |u| u on the projected area A.
  /// 1 is a bluff body at high Reynolds number (a cube broadside ~1.05, a flat plate ~1.2,
  /// a sphere ~0.47 for Re 1e3 - 2e5).
  double quadratic_drag = 1.0;
  /// k, m/s, >= 0: a linear drag rho k A u on the same area, for slow motion (skin friction,
  /// wave making); at 1 m/s and k = 0.01 it adds 2 % to the C_d = 1 drag.
  double linear_drag = 0.2;
  /// Sub-samples per water cell side, in [1, 16]: the body's envelopes on this grid give the
  /// water it displaces (its wake) and, for concave meshes only, their buoyancy.
  int samples_per_cell = 2;
  void validate() const;
};

/// What the water did to a body in one substep (forces averaged over the substep).
struct BodyWater {
  double submerged_volume = 0.0;          ///< m^3
  btVector3 centre_of_buoyancy{0, 0, 0};  ///< world, valid if submerged_volume > 0
  btVector3 buoyancy{0, 0, 0};            ///< N, rho g V, upward
  btVector3 drag{0, 0, 0};                ///< N, all drag (translation and rotation)
  btVector3 force{0, 0, 0};               ///< N, buoyancy + drag
  btVector3 torque{0, 0, 0};              ///< N m about the centre of mass
  double projected_area = 0.0;            ///< m^2, A along the relative flow (0 at rest)
  double water_level = 0.0;               ///< m, the fitted water plane's height at the centre of mass
};

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
