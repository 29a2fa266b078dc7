// WaterCoupling's btMultiBody links: adding one (a robot wading, a floating multibody).
// Once added, a link is floated like any body (coupled_multibody_link.h says how an
// articulated part moves and takes impulses).
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include "coupled_multibody_link.h"
#include "framed_body.h"
#include "shore/bullet/water_coupling.h"
#include "shore/core/error.h"
#include "water_coupling_parts.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
void WaterCoupling::add_link(btMultiBodyLinkCollider* link, WaterBodySettings body_settings) {
  const char* what = "bullet.WaterCoupling.add_link(link)";
  if (detached_) throw InvalidSetting(what, "after detach()", "a detached coupling takes no links: make a new one");
  const btMultiBodyDynamicsWorld& mb_world = coupling_detail::link_world(world_, link, what);
  coupling_detail::refuse_if_added(parts_->bodies.find(link) != nullptr, *link, what);
  if (link->getCollisionShape() == nullptr)
    throw InvalidSetting("bullet.WaterCoupling.add_link shape", "null", "the link must have a collision shape");
  parts_->enroll(*this,
                 coupling_detail::couple(std::make_unique<coupling_detail::CoupledMultiBodyLink>(*link, mb_world),
                                         settings_.frame),
                 body_settings, what, "link");
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
