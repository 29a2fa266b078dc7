#pragma once
// What TerrainCoupling::debugDraw and WaterCoupling::debugDraw draw into a btIDebugDraw,
// by the drawer's debug mode bits (getDebugMode()):
//
//   DBG_DrawContactPoints  terrain: every contact column of an added body (a cross on the
//                          column top); water: every added body's centre of buoyancy.
//   DBG_DrawNormals        terrain: its reaction: per contact column its bearing capacity
//                          (what the column can push with, a vertical line) and the net
//                          force on the body; water: the buoyancy at the centre of buoyancy.
//   DBG_DrawAabb           terrain: the outline of every Bullet tile of the terrain, on the
//                          ground; water: the outline of the water grid at rest level.
//
// Force arrows are scaled by the body's weight: an arrow of kArrowPerWeight metres is a
// force equal to m g (a body floating at rest shows one arrow that long). Nothing is
// drawn when none of these bits is set. btDiscreteDynamicsWorld::debugDrawWorld calls the
// actions' debugDraw only when DBG_DrawWireframe, DBG_DrawAabb or DBG_DrawNormals is set;
// call the couplings' debugDraw yourself to draw contact points alone.

#include <LinearMath/btIDebugDraw.h>
#include <LinearMath/btVector3.h>

#include "shore/bullet/config.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace debug_draw {

inline constexpr int kContactBits = btIDebugDraw::DBG_DrawContactPoints;
inline constexpr int kForceBits = btIDebugDraw::DBG_DrawNormals;
inline constexpr int kOutlineBits = btIDebugDraw::DBG_DrawAabb;
inline constexpr double kArrowPerWeight = 0.5;  ///< m of arrow for a force of m g
inline constexpr double kMaxArrow = 2.0;        ///< m: longer arrows are cut to this

/// Colours (RGB in [0, 1]).
inline const btVector3 kContactColour{1.0f, 0.85f, 0.1f};
inline const btVector3 kCapacityColour{0.95f, 0.45f, 0.1f};
inline const btVector3 kForceColour{0.9f, 0.1f, 0.1f};
inline const btVector3 kOutlineColour{0.2f, 0.9f, 0.9f};
inline const btVector3 kBuoyancyColour{0.1f, 0.4f, 1.0f};

/// A cross of half size `half` (m) in the three axis directions at p.
void cross(btIDebugDraw& d, const btVector3& p, double half, const btVector3& colour);
/// A line from `from` along `vector` with a small head at its tip.
void arrow(btIDebugDraw& d, const btVector3& from, const btVector3& vector, const btVector3& colour);
/// The arrow of a force (N) on a body of mass `mass` (kg): kArrowPerWeight m per m g, cut
/// to kMaxArrow; mass <= 0 (static or kinematic bodies): 1 m per 1000 N.
btVector3 force_arrow(const btVector3& force, double mass, double gravity);

}  // namespace debug_draw
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
