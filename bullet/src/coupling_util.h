#pragma once
// Small pieces both couplings need: the check that keeps a broken body out of the grids,
// and wall-clock timing of their stages.

#include <chrono>
#include <cmath>
#include <vector>

#include <BulletDynamics/Dynamics/btRigidBody.h>

#include "shore/bullet/config.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

inline bool finite(const btVector3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

/// False for a body with a non-finite pose or velocity, or moving faster than max_speed:
/// such a body is skipped (and counted) rather than allowed to poison soil or water.
inline bool body_is_sane(const btRigidBody& body, double max_speed) {
  const btTransform& t = body.getWorldTransform();
  if (!finite(t.getOrigin()) || !finite(t.getBasis()[0]) || !finite(t.getBasis()[1]) || !finite(t.getBasis()[2]))
    return false;
  const btVector3& v = body.getLinearVelocity();
  return finite(v) && finite(body.getAngularVelocity()) && v.length() <= max_speed;
}

/// The btRigidBody* of each element of a coupling's body list (elements, or pointers to
/// elements, with a `body` member).
template <class Entry>
std::vector<btRigidBody*> body_pointers(const std::vector<Entry>& entries) {
  std::vector<btRigidBody*> out;
  out.reserve(entries.size());
  for (const Entry& e : entries) {
    if constexpr (requires { e.body; })
      out.push_back(e.body);
    else
      out.push_back(e->body);
  }
  return out;
}

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
