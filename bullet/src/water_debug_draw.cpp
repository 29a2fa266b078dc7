// WaterCoupling::debugDraw: centres of buoyancy, buoyancy forces and the grid's outline,
// drawn from what the coupling exposes (its bodies, surface, settings).
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include "coupling_util.h"
#include "shore/bullet/buoyancy.h"
#include "shore/bullet/debug_draw.h"
#include "shore/bullet/envelope.h"
#include "shore/bullet/water_coupling.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace {

/// Buoyancy of the body in the surface as it is now: volume, centre, force (still water,
/// body at rest: no drag). Volume 0 if the body cannot be drawn.
WaterImpulse buoyancy_now(const water::Surface& surface, const FluidSettings& fluid, const btRigidBody& body) {
  const btCollisionShape& shape = *body.getCollisionShape();
  const double cell = surface.spacing() / fluid.samples_per_cell;
  const btVector3 com = body.getCenterOfMassPosition();
  // Samples at com + (k + 1/2) cell, as the coupling places them.
  const EnvelopeGrid grid{com.x() + 0.5 * cell, com.y() + 0.5 * cell, cell};
  if (!pose_rasterizable(body.getWorldTransform(), shape_reach(shape), grid)) return {};
  EnvelopeOptions options;
  options.upper = true;
  EnvelopeRaster env;
  rasterize_envelope(shape, body.getWorldTransform(), grid, options, env);
  const WaterSampler sampler{[&](double x, double y) { return surface.height_at(x, y); }, {}};
  const double mass = body.getInvMass() > 0 ? 1.0 / body.getInvMass() : 0.0;
  const btVector3 zero(0, 0, 0);
  // One second of impulse at rest in still water: the buoyancy force alone.
  return water_impulse(env, grid.origin_x, grid.origin_y, cell, sampler, fluid, com, zero, zero, mass, 1.0);
}

void draw_outline(btIDebugDraw& d, const water::Surface& s) {
  const auto z = btScalar(s.settings().rest_height);
  const auto x0 = btScalar(s.node_x(0)), x1 = btScalar(s.node_x(s.nx() - 1));
  const auto y0 = btScalar(s.node_y(0)), y1 = btScalar(s.node_y(s.ny() - 1));
  d.drawLine({x0, y0, z}, {x1, y0, z}, debug_draw::kOutlineColour);
  d.drawLine({x1, y0, z}, {x1, y1, z}, debug_draw::kOutlineColour);
  d.drawLine({x1, y1, z}, {x0, y1, z}, debug_draw::kOutlineColour);
  d.drawLine({x0, y1, z}, {x0, y0, z}, debug_draw::kOutlineColour);
}

}  // namespace

std::vector<btRigidBody*> WaterCoupling::bodies() const { return coupling_detail::body_pointers(bodies_); }

void WaterCoupling::debugDraw(btIDebugDraw* drawer) {
  if (drawer == nullptr) return;
  const int mode = drawer->getDebugMode();
  if (mode & (debug_draw::kContactBits | debug_draw::kForceBits)) {
    FluidSettings fluid = settings().fluid;
    fluid.density = surface().density();  // the coupling takes the density from the surface
    for (const btRigidBody* body : bodies()) {
      const WaterImpulse b = buoyancy_now(surface(), fluid, *body);
      if (!(b.submerged_volume > 0.0)) continue;
      const double mass = body->getInvMass() > 0 ? 1.0 / body->getInvMass() : 0.0;
      if (mode & debug_draw::kContactBits)
        debug_draw::cross(*drawer, b.centroid, 0.5 * surface().spacing(), debug_draw::kBuoyancyColour);
      if (mode & debug_draw::kForceBits)
        debug_draw::arrow(*drawer, b.centroid, debug_draw::force_arrow(b.linear, mass, fluid.gravity),
                          debug_draw::kBuoyancyColour);
    }
  }
  if (mode & debug_draw::kOutlineBits) draw_outline(*drawer, surface());
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
