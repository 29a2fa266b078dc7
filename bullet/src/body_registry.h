#pragma once
// Internal: the bodies a coupling serves, in the order added, each with the coupling's own
// record of it, and their lifetimes:
// - added once: adding an object again replaces its entry (moved to the end);
// - removed by remove_body, or forgotten when the world no longer holds an object it held
//   once (taken out of the world or deleted behind the coupling's back: noticed by address,
//   never read);
// - the world destroyed first: the coupling detaches before, and lets every body go.
// Also the broadphase filter bit a coupling takes from its bodies' collision masks.

#include <algorithm>
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>

#include "coupled_body.h"
#include "shore/bullet/config.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

/// The addresses of the world's collision objects, sorted: membership tests by address
/// that never read the object asked about (it may have been deleted).
class HeldObjects {
 public:
  explicit HeldObjects(const btCollisionWorld& world) {
    const btCollisionObjectArray& objects = world.getCollisionObjectArray();
    held_.reserve(static_cast<std::size_t>(objects.size()));
    for (int k = 0; k < objects.size(); ++k) held_.push_back(objects[k]);
    std::sort(held_.begin(), held_.end());
  }
  [[nodiscard]] bool holds(const void* object) const { return std::binary_search(held_.begin(), held_.end(), object); }

 private:
  std::vector<const void*> held_;
};

template <class Record>
class BodyRegistry {
 public:
  struct Entry {
    std::unique_ptr<CoupledBody> body;
    Record record;
    bool seen_in_world = false;  ///< the world held the object once (it is lost when it no longer does)
  };

  /// Adds the body at the end, after dropping an entry for the same object.
  Entry& add(std::unique_ptr<CoupledBody> body, Record record) {
    remove(&body->object());
    const bool in_world = body->proxy() != nullptr;
    entries_.push_back({std::move(body), std::move(record), in_world});
    return entries_.back();
  }
  /// Drops the object's entry; false if there was none.
  bool remove(const btCollisionObject* object) {
    return std::erase_if(entries_, [object](const Entry& e) { return &e.body->object() == object; }) > 0;
  }
  [[nodiscard]] Entry* find(const btCollisionObject* object) {
    for (Entry& e : entries_)
      if (&e.body->object() == object) return &e;
    return nullptr;
  }
  [[nodiscard]] const Entry* find(const btCollisionObject* object) const {
    return const_cast<BodyRegistry*>(this)->find(object);
  }
  /// Drops the entries whose held object (CoupledBody::held) the world held and no longer
  /// does. Returns how many.
  int forget_lost(const btCollisionWorld& world) {
    if (entries_.empty()) return 0;
    const HeldObjects held(world);
    for (Entry& e : entries_)
      if (held.holds(&e.body->held())) e.seen_in_world = true;
    const std::size_t before = entries_.size();
    std::erase_if(entries_, [&](const Entry& e) { return e.seen_in_world && !held.holds(&e.body->held()); });
    return static_cast<int>(before - entries_.size());
  }
  void clear() { entries_.clear(); }

  [[nodiscard]] std::size_t size() const noexcept { return entries_.size(); }
  [[nodiscard]] Entry& operator[](std::size_t k) { return entries_[k]; }
  [[nodiscard]] const Entry& operator[](std::size_t k) const { return entries_[k]; }
  auto begin() { return entries_.begin(); }
  auto end() { return entries_.end(); }
  auto begin() const { return entries_.begin(); }
  auto end() const { return entries_.end(); }

 private:
  std::vector<Entry> entries_;
};

/// Takes `bit` from the object's collision mask (Bullet then makes no pairs of it with
/// objects of that group) and drops the pairs it has with them already; does nothing
/// outside a world. `is_group_member` tells the group's objects apart.
template <class IsGroupMember>
void take_filter_bit(btCollisionWorld& world, btBroadphaseProxy* proxy, int bit, IsGroupMember&& is_group_member) {
  if (proxy == nullptr || (proxy->m_collisionFilterMask & bit) == 0) return;
  proxy->m_collisionFilterMask &= ~bit;
  btOverlappingPairCache* cache = world.getBroadphase()->getOverlappingPairCache();
  btBroadphasePairArray& pairs = cache->getOverlappingPairArray();
  std::vector<std::pair<btBroadphaseProxy*, btBroadphaseProxy*>> doomed;
  for (int k = 0; k < pairs.size(); ++k) {
    btBroadphaseProxy* a = pairs[k].m_pProxy0;
    btBroadphaseProxy* b = pairs[k].m_pProxy1;
    if (a != proxy && b != proxy) continue;
    const btBroadphaseProxy* other = a == proxy ? b : a;
    if (is_group_member(static_cast<const btCollisionObject*>(other->m_clientObject))) doomed.emplace_back(a, b);
  }
  for (const auto& [a, b] : doomed) cache->removeOverlappingPair(a, b, world.getDispatcher());
}

/// Gives `bit` back to the object's collision mask (outside a world: nothing).
inline void give_back_filter_bit(btBroadphaseProxy* proxy, int bit) {
  if (proxy != nullptr) proxy->m_collisionFilterMask |= bit;
}

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
