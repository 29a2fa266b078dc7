// TerrainCoupling's btMultiBody links: adding one (a robot's foot or wheel, a ragdoll's
// part). Once added, a link is served like any body (coupled_multibody_link.h says how an
// articulated part moves and takes impulses).
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include "coupled_multibody_link.h"
#include "framed_body.h"
#include "shore/bullet/terrain_coupling.h"
#include "shore/core/error.h"
#include "terrain_coupling_parts.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
void TerrainCoupling::add_link(btMultiBodyLinkCollider* link, TerrainBodySettings body_settings) {
  const char* what = "bullet.TerrainCoupling.add_link(link)";
  if (detached_) throw InvalidSetting(what, "after detach()", "a detached coupling takes no links: make a new one");
  const btMultiBodyDynamicsWorld& mb_world = coupling_detail::link_world(world_, link, what);
  coupling_detail::refuse_if_added(parts_->bodies.find(link) != nullptr, *link, what);
  body_settings.validate();
  parts_->refuse_if_held_elsewhere(*this, *link, what, "link");
  if (link->getCollisionShape() == nullptr)
    throw InvalidSetting("bullet.TerrainCoupling.add_link shape", "null", "the link must have a collision shape");
  auto coupled = coupling_detail::couple(std::make_unique<coupling_detail::CoupledMultiBodyLink>(*link, mb_world),
                                         settings_.frame);
  coupling_detail::TerrainBody record = parts_->record_for(*link, body_settings);
  // Bullet's multibody solver makes no continuous collision for links: enable_ccd does
  // nothing here.
  const bool owned = !parts_->rigid && coupled->dynamic() && body_settings.deform;
  parts_->enroll(std::move(coupled), std::move(record), owned);
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
