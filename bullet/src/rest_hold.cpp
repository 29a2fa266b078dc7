#include "rest_hold.h"

#include <cmath>

#include "bt_convert.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace contact_detail {

bool hold_at_rest(coupling_detail::CoupledBody& body, TerrainForce& last, const RestLimits& limits, double h) {
  const coupling_detail::Motion m = body.motion();
  const btVector3 v0 = m.linear, w0 = m.angular;
  const double inv_mass = body.inverse_mass();
  const btMatrix3x3 inv_inertia = body.inverse_inertia();
  const btVector3 v = v0 + last.force * btScalar(h * inv_mass);
  const btVector3 w = w0 + inv_inertia * (last.torque * btScalar(h));
  if (v.length() > btScalar(limits.speed) || w.length() > btScalar(limits.spin)) return false;
  // The terrain's whole impulse this substep is the one that stops the body: m (0 - v0) and
  // I (0 - w0). More than last substep's (a load growing) is for the solve to bound by what
  // the terrain bears.
  const btMatrix3x3 inertia = inv_inertia.inverse();
  const btVector3 force = -v0 * btScalar(1.0 / (h * inv_mass));
  if (force.length() > last.force.length() * btScalar(1.0 + 1e-6)) return false;
  last.force = force;
  last.torque = inertia * (-w0) * btScalar(1.0 / h);
  body.stop(h);
  return true;
}

void stop_sway(const coupling_detail::CoupledBody& body, const RestLimits& limits, SolverBody& solved,
               SolveResult& result) {
  const double speed = std::sqrt(dot(solved.v, solved.v)), spin = std::sqrt(dot(solved.w, solved.w));
  if (!(speed <= limits.speed && spin <= limits.spin) || !(solved.inv_mass > 0.0)) return;
  const btVector3 stop_spin = body.inverse_inertia().inverse() * (-to_bt(solved.w));
  result.impulse = result.impulse - solved.v * (1.0 / solved.inv_mass);
  result.angular_impulse = result.angular_impulse + to_vec3(stop_spin);
  solved.v = solved.w = {};
}

}  // namespace contact_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
