#pragma once
// Internal: the couplings of one kind that each Bullet world holds, so that add_body can
// find a body already added to another coupling of the same world (a body in two couplings
// whose areas overlap would be pushed by both). Bullet lists a world's actions only to
// itself (btDiscreteDynamicsWorld::m_actions is protected), telling a coupling apart from
// a game's own actions would need RTTI that games often compile out, and a collision
// object's user pointer and indices belong to the game. So each coupling enters itself
// here when made and leaves when detached or destroyed.
//
// One directory per coupling type for the whole process, shared by every world: entries
// are keyed by world, so couplings of different worlds never see each other, and a mutex
// guards the list, so worlds built and filled on different threads do not race on it.
// Only add_body reads it (never a substep), so the lock costs nothing that matters.

#include <algorithm>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include <BulletCollision/CollisionDispatch/btCollisionObject.h>

#include "shore/bullet/config.h"
#include "shore/bullet/terrain_tiles.h"
#include "shore/core/error.h"

class btCollisionWorld;

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

template <class Coupling>
class WorldDirectory {
 public:
  static void enter(const btCollisionWorld* world, const Coupling* coupling) {
    const std::lock_guard lock(mutex());
    entries().push_back({world, coupling});
  }
  /// Does nothing for a coupling not entered (or gone already).
  static void leave(const Coupling* coupling) {
    const std::lock_guard lock(mutex());
    std::erase_if(entries(), [coupling](const Entry& e) { return e.coupling == coupling; });
  }
  /// Calls f(other) for every other coupling entered for `world`, in the order entered,
  /// under the lock (f may throw; it must not enter or leave). Reading another coupling of
  /// the same world is as safe as using that world, which Bullet allows one thread at a time.
  template <class F>
  static void for_each_other(const btCollisionWorld* world, const Coupling* self, F&& f) {
    const std::lock_guard lock(mutex());
    for (const Entry& e : entries())
      if (e.world == world && e.coupling != self) f(*e.coupling);
  }

 private:
  struct Entry {
    const btCollisionWorld* world;
    const Coupling* coupling;
  };
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  static std::vector<Entry>& entries() {
    static std::vector<Entry> list;
    return list;
  }
};

/// How a refusal names a body: its address and its shape's kind (the collision object's
/// user fields are the game's, never read).
inline std::string body_text(const btCollisionObject& body) {
  std::ostringstream s;
  s << "body " << static_cast<const void*>(&body);
  if (body.getCollisionShape() != nullptr) s << " (" << body.getCollisionShape()->getName() << " shape)";
  return s.str();
}

/// "[x0, x1) x [y0, y1) m"; "everywhere" for the default Region.
inline std::string region_text(const Region& r) {
  if (r.everywhere()) return "everywhere (the default Region)";
  const auto edge = [](double v) -> std::string {
    if (v <= -Region::kUnbounded) return "-inf";
    if (v >= Region::kUnbounded) return "inf";
    return shore::detail::to_text(v);
  };
  return "[" + edge(r.x0) + ", " + edge(r.x1) + ") x [" + edge(r.y0) + ", " + edge(r.y1) + ") m";
}

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
