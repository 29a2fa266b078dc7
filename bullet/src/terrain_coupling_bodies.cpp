// TerrainCoupling's bodies: settings checks, adding and removing bodies, detaching, and
// what the coupling reports of them.
#include <string>
#include <utility>

#include "coupled_rigid_body.h"
#include "coupling_directory.h"
#include "coupling_util.h"
#include "framed_body.h"
#include "shore/bullet/soil_raycaster.h"
#include "shore/bullet/terrain_coupling.h"
#include "shore/core/error.h"
#include "terrain_coupling_parts.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace {
/// The terrain couplings of each world (a body in two of them over overlapping regions).
using Directory = coupling_detail::WorldDirectory<TerrainCoupling>;
}  // namespace

void TerrainContactSettings::validate() const {
  const Check c{"bullet.TerrainContactSettings"};
  c.in_closed("block_columns", block_columns, 1, 64);
  c.in_closed("iterations", iterations, 1, 1000);
  c.in_closed("resting_iterations", resting_iterations, 1, 1000);
  c.in_closed("follow_drift", follow_drift, 0.0, 2.0);
  c.non_negative("follow_speed", follow_speed);
}

void TerrainBodySettings::validate() const {
  const Check c{"bullet.TerrainBodySettings"};
  c.in_left_open("ccd_motion_share", ccd_motion_share, 0.0, 1.0);
  c.in_left_open("ccd_sphere_share", ccd_sphere_share, 0.0, 1.0);
}

void TerrainCouplingSettings::validate() const {
  tiles.validate();
  contact.validate();
  const Check c{"bullet.TerrainCouplingSettings"};
  c.positive("cover_margin", cover_margin);
  c.positive("max_speed", max_speed);
  c.positive("rest_speed", rest_speed);
  c.positive("rest_spin", rest_spin);
  c.in_closed("step_interval", step_interval, 0.0, 0.125);
  c.in_closed("raycast_wheel_margin", raycast_wheel_margin, 0, 256);
  frame.validate("bullet.TerrainCouplingSettings.frame");
}

TerrainCoupling::Parts::Parts(btDiscreteDynamicsWorld& in_world, terrain::Terrain& in_terrain,
                              const TerrainCouplingSettings& in_settings, TerrainCouplingStats& in_stats)
    : world(in_world),
      terrain(in_terrain),
      settings(in_settings),
      stats(in_stats),
      tiles(in_world, in_terrain, in_settings.tiles),
      rasterizer(
          EnvelopeGrid{in_terrain.settings().origin_x, in_terrain.settings().origin_y, in_terrain.settings().cell},
          coupling_detail::nominal_solid()),
      rigid(in_terrain.settings().material.rigid),
      framed(!in_settings.frame.identity()),
      to_ground(in_settings.frame.to_ground()) {
  wheels.set_ground([this](const btVector3& at) { return !rigid && on_terrain(at); });
}

TerrainCoupling::TerrainCoupling(btDiscreteDynamicsWorld& world, terrain::Terrain& terrain,
                                 TerrainCouplingSettings settings)
    : world_(world),
      terrain_(terrain),
      settings_(std::move(settings)),
      parts_(std::make_unique<Parts>(world_, terrain_, settings_, stats_)) {
  settings_.validate();
  parts_->tiles.set_region(settings_.region);
  parts_->tiles.set_frame(settings_.frame);
  parts_->wheels.set_frame(settings_.frame);
  parts_->wheels.set_margin(settings_.raycast_wheel_margin);
  parts_->tiles.set_collision_group(parts_->rigid ? int(btBroadphaseProxy::StaticFilter)
                                                  : settings_.terrain_filter_bit);
  world_.addAction(this);
  Directory::enter(&world_, this);
}

TerrainCoupling::~TerrainCoupling() { detach(); }

void TerrainCoupling::detach() {
  if (detached_) return;
  // Bullet's tile contact back for the bodies still in the world.
  const coupling_detail::HeldObjects held(world_);
  for (const Parts::Entry& e : parts_->bodies)
    if (held.holds(&e.body->object()))
      coupling_detail::give_back_filter_bit(e.body->proxy(), settings_.terrain_filter_bit);
  parts_->bodies.clear();
  parts_->imprints.clear();
  parts_->tiles.remove_all();
  world_.removeAction(this);
  Directory::leave(this);
  detached_ = true;
}

void TerrainCoupling::add_body(btRigidBody* body, TerrainBodySettings body_settings) {
  const char* what = "bullet.TerrainCoupling.add_body(body)";
  if (body == nullptr) throw InvalidSetting(what, "null", "must be a rigid body");
  if (detached_) throw InvalidSetting(what, "after detach()", "a detached coupling takes no bodies: make a new one");
  body_settings.validate();
  parts_->refuse_if_held_elsewhere(*this, *body, what, "body");
  auto coupled = coupling_detail::couple(std::make_unique<coupling_detail::CoupledRigidBody>(*body), settings_.frame);
  coupling_detail::TerrainBody record = parts_->record_for(*body, body_settings);
  const bool owned = !parts_->rigid && coupled->dynamic() && body_settings.deform;
  if (owned && body->getBroadphaseHandle() == nullptr)
    throw InvalidSetting(what, "not in the world", "add the body to the dynamics world before add_body");
  remove_body(body);
  if (body_settings.enable_ccd && coupled->dynamic()) {
    btVector3 lo, hi;
    body->getCollisionShape()->getAabb(btTransform::getIdentity(), lo, hi);
    const btVector3 size = hi - lo;
    const btScalar thinnest = size[size.minAxis()];
    body->setCcdMotionThreshold(btScalar(body_settings.ccd_motion_share) * thinnest);
    body->setCcdSweptSphereRadius(btScalar(body_settings.ccd_sphere_share) * thinnest);
  }
  parts_->enroll(std::move(coupled), std::move(record), owned);
}

void TerrainCoupling::Parts::refuse_if_held_elsewhere(const TerrainCoupling& self, const btCollisionObject& object,
                                                      const char* what, const char* kind) const {
  Directory::for_each_other(&world, &self, [&](const TerrainCoupling& other) {
    if (other.parts_->bodies.find(&object) == nullptr || !other.settings_.region.overlaps(settings.region)) return;
    throw InvalidSetting(what,
                         coupling_detail::body_text(object) +
                             ", already in another TerrainCoupling of this world whose region " +
                             coupling_detail::region_text(other.settings_.region) + " overlaps this one's " +
                             coupling_detail::region_text(settings.region),
                         std::string("a ") + kind +
                             " may be in several terrain couplings only if their regions are disjoint (else "
                             "both terrains would push it): remove_body it from the other first, or give the "
                             "couplings disjoint regions");
  });
}

coupling_detail::TerrainBody TerrainCoupling::Parts::record_for(const btCollisionObject& object,
                                                                const TerrainBodySettings& body_settings) const {
  coupling_detail::TerrainBody record;
  record.settings = body_settings;
  record.shape.shape = object.getCollisionShape();
  if (record.shape.shape != nullptr) record.shape.scaling = record.shape.shape->getLocalScaling();
  if (body_settings.deform)  // once: then rasterizing it never fails for a sane pose
    record.shape.reach =
        coupling_detail::check_terrain_shape(*object.getCollisionShape(), rasterizer.grid().cell, rasterizer.options());
  return record;
}

void TerrainCoupling::Parts::enroll(std::unique_ptr<coupling_detail::CoupledBody> coupled,
                                    coupling_detail::TerrainBody record, bool owned) {
  // Shore owns this body's contact with soft soil: Bullet must not collide it with the tiles.
  if (owned) take_filter_bit(*coupled);
  Entry& e = bodies.add(std::move(coupled), std::move(record));
  if (!sane(*e.body)) return;
  if (e.record.settings.deform && can_rasterize(e)) rasterize(e);
  btVector3 lo, hi;  // tiles under it at once
  e.body->shape()->getAabb(e.body->pose(), lo, hi);
  const double m = settings.cover_margin;
  tiles.ensure_cover(lo.x() - m, lo.y() - m, hi.x() + m, hi.y() + m);
}

void TerrainCoupling::remove_body(const btCollisionObject* body) {
  const Parts::Entry* e = parts_->bodies.find(body);
  if (e == nullptr) return;
  coupling_detail::give_back_filter_bit(e->body->proxy(), settings_.terrain_filter_bit);
  parts_->bodies.remove(body);
}

void TerrainCoupling::add_vehicle(btRaycastVehicle* vehicle, std::span<const double> wheel_widths,
                                  const SoilRaycaster* raycaster) {
  if (detached_)
    throw InvalidSetting("bullet.TerrainCoupling.add_vehicle(vehicle)", "after detach()",
                         "a detached coupling takes no vehicles: make a new one");
  if (raycaster != nullptr && &raycaster->coupling() != this)
    throw InvalidSetting("bullet.TerrainCoupling.add_vehicle(raycaster)", "another coupling's",
                         "must be built with this coupling, or null");
  parts_->wheels.add(vehicle, wheel_widths, terrain_.settings().cell, coupling_detail::nominal_solid(),
                     raycaster != nullptr);
}

void TerrainCoupling::remove_vehicle(const btRaycastVehicle* vehicle) { parts_->wheels.remove(vehicle); }

double TerrainCoupling::wheel_push(const btRaycastVehicle* vehicle, int wheel) const {
  return parts_->wheels.push(vehicle, wheel);
}

double TerrainCoupling::wheel_side_push(const btRaycastVehicle* vehicle, int wheel) const {
  return parts_->wheels.side_push(vehicle, wheel);
}

TerrainForce TerrainCoupling::terrain_force(const btCollisionObject* body) const {
  const Parts::Entry* e = parts_->bodies.find(body);
  if (e == nullptr) return {};
  TerrainForce f = e->record.contact.last;  // in the ground's coordinates
  if (parts_->framed) {
    const GroundFrame& frame = settings_.frame;
    f.force = frame.direction_to_world(f.force);
    f.torque = frame.direction_to_world(f.torque);
    f.normal_force = frame.direction_to_world(f.normal_force);
  }
  return f;
}

std::vector<const btCollisionObject*> TerrainCoupling::bodies() const {
  std::vector<const btCollisionObject*> out;
  out.reserve(parts_->bodies.size());
  for (const Parts::Entry& e : parts_->bodies) out.push_back(&e.body->object());
  return out;
}

TerrainTiles& TerrainCoupling::tiles() noexcept { return parts_->tiles; }

bool TerrainCoupling::Parts::sane(const coupling_detail::CoupledBody& body) const {
  return coupling_detail::body_is_sane(body, settings.max_speed);
}

void TerrainCoupling::Parts::own_terrain_contact(coupling_detail::CoupledBody& body) {
  if (rigid || !body.dynamic()) return;
  take_filter_bit(body);
}

void TerrainCoupling::Parts::take_filter_bit(coupling_detail::CoupledBody& body) {
  coupling_detail::take_filter_bit(world, body.proxy(), settings.terrain_filter_bit,
                                   [this](const btCollisionObject* other) { return tiles.is_tile(other); });
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
