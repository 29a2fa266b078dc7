#pragma once
// Internal: what a WaterCoupling keeps of each body and besides its settings and
// statistics, and the stages of its substep, defined by job: the substep and floating in
// water_coupling.cpp, where a body sits in the water in water_submersion.cpp, the water it
// displaces in water_displacement.cpp, the checkpoint in water_coupling_state.cpp.

#include <memory>
#include <vector>

#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <BulletDynamics/Vehicle/btRaycastVehicle.h>

#include "body_registry.h"
#include "coupled_body.h"
#include "envelope_internal.h"
#include "shore/bullet/buoyancy.h"
#include "shore/bullet/envelope.h"
#include "shore/bullet/water_coupling.h"
#include "shore/core/envelope.h"
#include "shore/water/surface.h"
#include "water_shape.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

/// What the water coupling keeps of one body.
struct WaterBody {
  WaterBodySettings settings;
  water_detail::WaterShape shape;
  /// Sub-sample envelopes (EnvelopeRasters on the sub-sample grid, water_displacement.cpp)
  /// at the pose the displacement was last taken from, and at the present pose.
  EnvelopeRaster reference, current;
  btTransform reference_pose = btTransform::getIdentity();
  bool have_reference = false;
  BodyWater last;                                  ///< the water's push in the last substep
  std::unique_ptr<EnvelopeRasterizer> rasterizer;  ///< sampled parts only
  water_detail::Submerged wet;
};

/// A raycast vehicle whose wheels the water coupling serves: its wheels' collision objects
/// (coupled_raycast_wheel.h), the keys of their entries, in wheel order.
struct WaterVehicle {
  const btRaycastVehicle* vehicle = nullptr;
  std::vector<const btCollisionObject*> wheels;
};

/// Scratch reused across bodies and substeps.
struct WaterWorkspace {
  std::vector<envelope_detail::Frame> frames;
  std::vector<water_detail::WorldPlanes> planes;
  std::vector<double> heights, velocities, ds, smooth, lo, hi;
};

/// The node envelope's nominal solid: buoyancy needs the body's true volume.
EnvelopeOptions nominal_with_upper();
/// The grid of sub-samples: sub-sample k at origin + (k + 1/2) h / S - h / 2.
EnvelopeGrid sub_grid(const water::Surface& s, int per_cell);

}  // namespace coupling_detail

struct WaterCoupling::Parts {
  using Entry = coupling_detail::BodyRegistry<coupling_detail::WaterBody>::Entry;

  Parts(btDiscreteDynamicsWorld& in_world, water::Surface& in_surface, const WaterCouplingSettings& in_settings,
        WaterCouplingStats& in_stats)
      : world(in_world), surface(in_surface), settings(in_settings), stats(in_stats) {}

  btDiscreteDynamicsWorld& world;
  water::Surface& surface;
  const WaterCouplingSettings& settings;
  WaterCouplingStats& stats;
  coupling_detail::BodyRegistry<coupling_detail::WaterBody> bodies;
  std::vector<coupling_detail::WaterVehicle> vehicles;  ///< their wheels are entries of `bodies`
  coupling_detail::WaterWorkspace work;

  /// A checked body or link joins (water_coupling.cpp): refused if another water coupling
  /// of the world holds it over an overlapping surface (`what`: the call, `kind`: "body" or
  /// "link", for the message); its shape prepared, its displacement tracked from here.
  void enroll(const WaterCoupling& self, std::unique_ptr<coupling_detail::CoupledBody> coupled,
              WaterBodySettings body_settings, const char* what, const char* kind);
  /// Drops the vehicles whose wheels the registry forgot (their chassis left the world).
  void forget_lost_vehicles();
  /// The last substep's forces on a body, in world coordinates.
  [[nodiscard]] BodyWater in_world(const Entry& e) const;
  /// Buoyancy and drag of one body for a substep of h, then its displacement
  /// (water_coupling.cpp).
  void float_body(Entry& e, double h);
  /// Samples the body's envelopes at its pose and adds what it swept to the water
  /// (water_displacement.cpp).
  void displace(Entry& e);
  /// The body's sub-sample envelopes at its pose, into its record's `current`.
  void sample_envelopes(Entry& e);
};

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
