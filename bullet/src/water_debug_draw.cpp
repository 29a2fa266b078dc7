// WaterCoupling::debugDraw: centres of buoyancy, buoyancy forces and the grid's outline,
// drawn from what the coupling exposes (its bodies, the forces of the last substep, surface).
#include "framed_draw.h"
#include "shore/bullet/buoyancy.h"
#include "shore/bullet/debug_draw.h"
#include "shore/bullet/water_coupling.h"
#include "water_coupling_parts.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace {

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

void WaterCoupling::debugDraw(btIDebugDraw* world_drawer) {
  if (world_drawer == nullptr) return;
  // Drawn in the water's coordinates (the coupling keeps its forces so), taken into the
  // world's by the frame.
  coupling_detail::FramedDraw framed(*world_drawer, settings().frame.to_world());
  btIDebugDraw* drawer = settings().frame.identity() ? world_drawer : &framed;
  const int mode = drawer->getDebugMode();
  if (mode & (debug_draw::kContactBits | debug_draw::kForceBits)) {
    for (const Parts::Entry& e : parts_->bodies) {
      // The buoyancy the last substep applied, not a fresh estimate.
      const BodyWater& b = e.record.last;
      if (!(b.submerged_volume > 0.0)) continue;
      const double mass = e.body->inverse_mass() > 0 ? 1.0 / e.body->inverse_mass() : 0.0;
      if (mode & debug_draw::kContactBits)
        debug_draw::cross(*drawer, b.centre_of_buoyancy, 0.5 * surface().spacing(), debug_draw::kBuoyancyColour);
      if (mode & debug_draw::kForceBits)
        debug_draw::arrow(*drawer, b.centre_of_buoyancy,
                          debug_draw::force_arrow(b.buoyancy, mass, settings().fluid.gravity),
                          debug_draw::kBuoyancyColour);
    }
  }
  if (mode & debug_draw::kOutlineBits) draw_outline(*drawer, surface());
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
