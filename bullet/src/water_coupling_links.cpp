// WaterCoupling's btMultiBody links: adding one (a robot wading, a floating multibody).
// Once added, a link is floated like any body (coupled_multibody_link.h says how an
// articulated part moves and takes impulses).
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include "coupled_multibody_link.h"
#include "coupling_directory.h"
#include "framed_body.h"
#include "shore/bullet/water_coupling.h"
#include "shore/core/error.h"
#include "water_coupling_parts.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace {
using Directory = coupling_detail::WorldDirectory<WaterCoupling>;

/// The rectangle a surface covers: node (i, j) stands for the cell of side h around it.
Region covered(const water::Surface& s) {
  const double h = s.spacing();
  return {s.node_x(0) - 0.5 * h, s.node_y(0) - 0.5 * h, s.node_x(s.nx() - 1) + 0.5 * h, s.node_y(s.ny() - 1) + 0.5 * h};
}
}  // namespace

void WaterCoupling::add_link(btMultiBodyLinkCollider* link, WaterBodySettings body_settings) {
  const char* what = "bullet.WaterCoupling.add_link(link)";
  if (detached_) throw InvalidSetting(what, "after detach()", "a detached coupling takes no links: make a new one");
  const btMultiBodyDynamicsWorld& mb_world = coupling_detail::link_world(world_, link, what);
  if (link->getCollisionShape() == nullptr)
    throw InvalidSetting("bullet.WaterCoupling.add_link shape", "null", "the link must have a collision shape");
  Directory::for_each_other(&world_, this, [&](const WaterCoupling& other) {
    const Region mine = covered(surface_), theirs = covered(other.surface_);
    if (other.parts_->bodies.find(link) == nullptr || !theirs.overlaps(mine)) return;
    throw InvalidSetting(what,
                         coupling_detail::body_text(*link) + ", already in another WaterCoupling of this world whose " +
                             "water " + coupling_detail::region_text(theirs) + " overlaps this one's " +
                             coupling_detail::region_text(mine),
                         "a link may be in several water couplings only if their surfaces do not overlap: "
                         "remove_body it from the other first");
  });
  coupling_detail::WaterBody record;
  record.settings = body_settings;
  record.shape = water_detail::prepare_shape(*link->getCollisionShape());
  if (record.shape.sampled) {
    const EnvelopeGrid grid = coupling_detail::sub_grid(surface_, settings_.fluid.samples_per_cell);
    (void)check_rasterizable(*link->getCollisionShape(), grid.cell, coupling_detail::nominal_with_upper());
    record.rasterizer = std::make_unique<EnvelopeRasterizer>(grid, coupling_detail::nominal_with_upper());
  }
  auto coupled = coupling_detail::couple(std::make_unique<coupling_detail::CoupledMultiBodyLink>(*link, mb_world),
                                         settings_.frame);
  Parts::Entry& added = parts_->bodies.add(std::move(coupled), std::move(record));
  if (added.record.settings.disturb) parts_->displace(added);  // tracking starts at this pose
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
