#pragma once
// Small pieces both couplings need: the check that keeps a broken body out of the grids,
// and wall-clock timing of their stages.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>

#include <BulletDynamics/Dynamics/btRigidBody.h>

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
/// allowed to poison soil or water.
inline bool body_is_sane(const btRigidBody& body, double max_speed) {
  const btTransform& t = body.getWorldTransform();
  if (!finite(t.getOrigin()) || !finite(t.getBasis()[0]) || !finite(t.getBasis()[1]) || !finite(t.getBasis()[2]))
    return false;
  if (!within(t.getOrigin(), kMaxCoordinate)) return false;
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

/// The addresses of the world's rigid bodies, sorted: membership tests by address that
/// never read the body asked about (it may have been deleted).
inline std::vector<const void*> bodies_held_by(const btCollisionWorld& world) {
  const btCollisionObjectArray& objects = world.getCollisionObjectArray();
  std::vector<const void*> held;
  held.reserve(static_cast<std::size_t>(objects.size()));
  for (int k = 0; k < objects.size(); ++k)
    if (const btRigidBody* body = btRigidBody::upcast(objects[k])) held.push_back(body);
  std::sort(held.begin(), held.end());
  return held;
}

inline bool holds(const std::vector<const void*>& held, const btRigidBody* body) {
  return std::binary_search(held.begin(), held.end(), static_cast<const void*>(body));
}

/// Drops the entries (elements with `body` and `seen_in_world` members) whose body was in
/// the world and no longer is: taken out of it, or deleted, without remove_body. Compares
/// addresses only. Returns how many were dropped.
template <class Entry, class Access>
int forget_bodies_out_of(const btCollisionWorld& world, std::vector<Entry>& entries, Access entry) {
  if (entries.empty()) return 0;
  const std::vector<const void*> held = bodies_held_by(world);
  for (Entry& e : entries)
    if (holds(held, entry(e).body)) entry(e).seen_in_world = true;
  const std::size_t before = entries.size();
  std::erase_if(entries, [&](Entry& e) { return entry(e).seen_in_world && !holds(held, entry(e).body); });
  return static_cast<int>(before - entries.size());
}

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
