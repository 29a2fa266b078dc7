#pragma once
// Internal: bodies at rest on the terrain cost almost nothing. A body the terrain holds
// still needs from it what it needed last substep (the same impulse cancels the same
// forces); holding it so is a few dozen operations instead of a contact solve.

#include "contact_solver.h"
#include "coupled_body.h"
#include "shore/bullet/config.h"
#include "shore/bullet/terrain_coupling.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace contact_detail {

/// Below these a body is at rest (TerrainCouplingSettings::rest_speed, rest_spin).
struct RestLimits {
  double speed = 0.0;  ///< m/s
  double spin = 0.0;   ///< rad/s
};

/// Holds a body at rest with last substep's force `last` (updated to the force that stops it
/// this substep) and stops it. False, touching nothing, if that would leave it moving
/// faster than the limits or take a larger force than last substep's (something pushed it,
/// or its load grew: the solve bounds that by what the terrain bears).
bool hold_at_rest(coupling_detail::CoupledBody& body, TerrainForce& last, const RestLimits& limits, double h);

/// A solve that leaves a held body moving slower than the limits (unloading columns are
/// springs: a settled body keeps swaying by far less than that) stops it, the terrain
/// taking what is left: the next substep needs the force this one ended with, and
/// hold_at_rest holds it.
void stop_sway(const coupling_detail::CoupledBody& body, const RestLimits& limits, SolverBody& solved,
               SolveResult& result);

}  // namespace contact_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
