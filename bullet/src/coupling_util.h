#pragma once
// Internal: small pieces both couplings need: the check that keeps a broken body out of the
// grids, and wall-clock timing of their stages.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>

#include "coupled_body.h"
#include "shore/bullet/config.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

inline bool finite(const btVector3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

/// How far from the origin a coupled body may be, m, along any axis: beyond it (a body
/// flung away, a corrupt pose) no soil or water column index is representable, so the body
/// is skipped like a non-finite one.
inline constexpr double kMaxCoordinate = 1e9;

/// Whether every component of v lies within [-bound, bound] (false for NaN).
inline bool within(const btVector3& v, double bound) {
  return std::fabs(double(v.x())) <= bound && std::fabs(double(v.y())) <= bound && std::fabs(double(v.z())) <= bound;
}

/// False for a body with a non-finite pose or velocity, farther than kMaxCoordinate from the
/// origin, or moving faster than max_speed: such a body is skipped (and counted) rather than
/// allowed to poison terrain or water.
inline bool motion_is_sane(const btTransform& pose, const btVector3& linear, const btVector3& angular,
                           double max_speed) {
  const btTransform& t = pose;
  if (!finite(t.getOrigin()) || !finite(t.getBasis()[0]) || !finite(t.getBasis()[1]) || !finite(t.getBasis()[2]))
    return false;
  if (!within(t.getOrigin(), kMaxCoordinate)) return false;
  return finite(linear) && finite(angular) && linear.length() <= max_speed;
}
inline bool body_is_sane(const CoupledBody& body, double max_speed) {
  const Motion m = body.motion();
  return motion_is_sane(body.pose(), m.linear, m.angular, max_speed);
}

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
