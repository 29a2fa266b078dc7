// TerrainCoupling::debugDraw: contact columns, the terrain's reaction and tile outlines,
// drawn from what the coupling keeps (its bodies and their last forces, terrain, tiles) so
// that the coupling's own substep code stays free of drawing.
#include <algorithm>
#include <optional>

#include <BulletCollision/CollisionDispatch/btCollisionObject.h>

#include "coupling_util.h"
#include "framed_draw.h"
#include "shore/bullet/debug_draw.h"
#include "shore/bullet/envelope.h"
#include "shore/bullet/terrain_coupling.h"
#include "terrain_coupling_parts.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace {

constexpr double kLift = 0.003;  // m above the ground, so lines are not hidden in it

EnvelopeGrid terrain_grid(const terrain::Terrain& terrain) {
  return {terrain.settings().origin_x, terrain.settings().origin_y, terrain.settings().cell};
}

/// The terrain's contact under the body's lower envelope at its present pose (the columns
/// the terrain pushes from, as the coupling's solve sees them: within the unloading columns'
/// elastic reach too), clipped to the coupling's region; empty if the body cannot be drawn.
terrain::ContactPatch contact_of(const terrain::Terrain& terrain, const Region& region,
                                 const coupling_detail::CoupledBody& body) {
  const btCollisionShape& shape = *body.shape();
  const EnvelopeGrid grid = terrain_grid(terrain);
  if (!pose_rasterizable(body.pose(), shape_reach(shape), grid)) return {};
  EnvelopeRaster env;
  rasterize_envelope(shape, body.pose(), grid, EnvelopeOptions{}, env);
  if (!region.everywhere())
    for (int b = 0; b < env.ny; ++b)
      for (int a = 0; a < env.nx; ++a)
        if (!region.contains(terrain.column_x(env.i0 + a), terrain.column_y(env.j0 + b)))
          env.lower[env.index(env.i0 + a, env.j0 + b)] = EnvelopeRaster::kNoLower;
  terrain::ContactPatch patch;
  terrain.contact(env, {}, nullptr, patch);
  return patch;
}

btVector3 column_top(const terrain::Terrain& terrain, std::int64_t i, std::int64_t j) {
  return {btScalar(terrain.column_x(i)), btScalar(terrain.column_y(j)), btScalar(terrain.height(i, j) + kLift)};
}

void draw_body_contact(btIDebugDraw& d, const TerrainCoupling& coupling, const terrain::Terrain& terrain,
                       const coupling_detail::CoupledBody& body, const TerrainForce& pushed, int mode) {
  const terrain::ContactPatch patch = contact_of(terrain, coupling.settings().region, body);
  if (patch.elements.empty()) return;
  const double half = 0.35 * terrain.settings().cell;
  const double mass = body.inverse_mass() > 0 ? 1.0 / body.inverse_mass() : 0.0;
  const double g0 = coupling.world().getGravity().length();
  const double g = g0 > 0 ? g0 : 9.81;
  btVector3 centre(0, 0, 0);
  double weight = 0.0;
  for (const terrain::ContactElement& e : patch.elements) {
    if (e.wall) continue;
    const btVector3 top = column_top(terrain, e.i, e.j);
    const double force = e.pressure * e.area * e.normal.z;  // the most it bears, vertically
    if (mode & debug_draw::kContactBits) debug_draw::cross(d, top, half, debug_draw::kContactColour);
    if ((mode & debug_draw::kForceBits) && std::isfinite(force) && force > 0.0)
      d.drawLine(top, top + debug_draw::force_arrow(btVector3(0, 0, btScalar(force)), mass, g),
                 debug_draw::kCapacityColour);
    const double w = std::isfinite(force) && force > 0.0 ? force : 1.0;
    centre += top * btScalar(w);
    weight += w;
  }
  if (!(mode & debug_draw::kForceBits) || weight <= 0.0) return;
  debug_draw::arrow(d, centre / btScalar(weight), debug_draw::force_arrow(pushed.force, mass, g),
                    debug_draw::kForceColour);
}

/// The outline of one Bullet tile, following the ground along its four edges.
void draw_tile_outline(btIDebugDraw& d, const terrain::Terrain& terrain, const btCollisionObject& tile,
                       const btTransform& to_ground) {
  btVector3 lo, hi;
  const btCollisionShape& shape = *tile.getCollisionShape();
  shape.getAabb(to_ground * tile.getWorldTransform(), lo, hi);
  const btScalar m = shape.getMargin();  // Bullet pads a heightfield's box by its margin
  const std::int64_t i0 = terrain.column_i(lo.x() + m), i1 = terrain.column_i(hi.x() - m);
  const std::int64_t j0 = terrain.column_j(lo.y() + m), j1 = terrain.column_j(hi.y() - m);
  auto edge = [&](std::int64_t ia, std::int64_t ja, std::int64_t di, std::int64_t dj, std::int64_t n) {
    for (std::int64_t k = 0; k < n; ++k)
      d.drawLine(column_top(terrain, ia + k * di, ja + k * dj),
                 column_top(terrain, ia + (k + 1) * di, ja + (k + 1) * dj), debug_draw::kOutlineColour);
  };
  edge(i0, j0, 1, 0, i1 - i0);
  edge(i0, j1, 1, 0, i1 - i0);
  edge(i0, j0, 0, 1, j1 - j0);
  edge(i1, j0, 0, 1, j1 - j0);
}

}  // namespace

void TerrainCoupling::debugDraw(btIDebugDraw* world_drawer) {
  if (world_drawer == nullptr) return;
  // Everything is drawn in the terrain's coordinates (the body's pose and force too: the
  // coupling keeps them so) and taken into the world's by the frame.
  coupling_detail::FramedDraw framed(*world_drawer, settings_.frame.to_world());
  btIDebugDraw* drawer = parts_->framed ? &framed : world_drawer;
  const int mode = drawer->getDebugMode();
  const terrain::Terrain& ground = terrain();
  if ((mode & (debug_draw::kContactBits | debug_draw::kForceBits)) && !ground.settings().material.rigid)
    for (const Parts::Entry& e : parts_->bodies)
      draw_body_contact(*drawer, *this, ground, *e.body, e.record.contact.last, mode);
  if (mode & debug_draw::kOutlineBits) {
    const btCollisionObjectArray& objects = world().getCollisionObjectArray();
    for (int k = 0; k < objects.size(); ++k)
      if (tiles().is_tile(objects[k])) draw_tile_outline(*drawer, ground, *objects[k], parts_->to_ground);
  }
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
