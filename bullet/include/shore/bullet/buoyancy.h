#pragma once
// Buoyancy and drag of one body from its envelopes and the live water surface.
//
// The body's lower and upper envelopes are sampled on a grid finer than the water's (4 x 4
// samples per water cell by default: with one sample per cell a box shifted by a quarter
// cell heels by up to 0.7 rad). At each sample the submerged length is
//   s = clamp(water_height - lower, 0, upper - lower)
// and the submerged volume is the sum of s * sample_area, its centroid the s-weighted
// mean of the submerged segments' midpoints. Buoyancy rho g V acts upward at that
// centroid (so a heeled boat rights itself); drag acts per sample on the relative velocity
// of the body point there against the water. Both are returned as impulses for one
// substep, because forces added inside a Bullet substep accumulate across substeps.

#include <functional>
#include <vector>

#include <LinearMath/btVector3.h>

#include "shore/bullet/config.h"
#include "shore/core/envelope.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

struct FluidSettings {
  double density = 1000.0;      ///< kg/m^3, water density, > 0
  double gravity = 9.81;        ///< m/s^2, > 0
  double linear_drag = 0.5;     ///< m/s: linear drag rho A k u per unit wetted area, >= 0
  double quadratic_drag = 1.0;  ///< dimensionless C_d in 0.5 rho C_d A |u| u, >= 0
  int samples_per_cell = 4;     ///< buoyancy samples per water cell side, in [1, 16]
  void validate() const;
};

/// What the water does to a body in one substep.
struct WaterImpulse {
  double submerged_volume = 0.0;  ///< m^3
  btVector3 centroid{0, 0, 0};    ///< world centre of buoyancy (valid if volume > 0)
  btVector3 linear{0, 0, 0};      ///< N s, total impulse (buoyancy + drag)
  btVector3 angular{0, 0, 0};     ///< N m s, about the centre of mass
};

/// The water surface as the coupling sees it: height and velocity at a world position.
struct WaterSampler {
  std::function<double(double x, double y)> height;
  std::function<btVector3(double x, double y)> velocity;  ///< may be empty: still water
};

/// Buoyancy and drag impulses over a substep h for a body whose envelopes (lower AND
/// upper) are in `env` (its grid spacing is `sample_cell`), with centre of mass `com`,
/// linear velocity v and angular velocity w. Drag impulses are clamped so they never
/// reverse the relative velocity of a sample within one substep (stable for light bodies
/// at large steps).
WaterImpulse water_impulse(const EnvelopeRaster& env, double origin_x, double origin_y, double sample_cell,
                           const WaterSampler& water, const FluidSettings& fluid, const btVector3& com,
                           const btVector3& v, const btVector3& w, double body_mass, double h);

/// Submerged length of every sample (same layout as env), for the body-to-water
/// displacement; returns the total submerged volume.
double submerged_lengths(const EnvelopeRaster& env, double origin_x, double origin_y, double sample_cell,
                         const WaterSampler& water, std::vector<double>& lengths);

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
