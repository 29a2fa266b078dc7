#include "shore/bullet/terrain_coupling.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <BulletCollision/BroadphaseCollision/btDispatcher.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <LinearMath/btTransformUtil.h>

#include "bt_convert.h"
#include "checkpoint_bytes.h"
#include "coupling_directory.h"
#include "coupling_util.h"
#include "shore/bullet/envelope.h"
#include "shore/core/error.h"
#include "soil_solver.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

namespace {
using coupling_detail::Clock;
using coupling_detail::seconds_since;
/// The terrain couplings of each world (a body in two of them over overlapping regions).
using Directory = coupling_detail::WorldDirectory<TerrainCoupling>;

/// The body's true shape, without Bullet's collision margin: Shore, not Bullet, makes the
/// contact of added bodies with soft soil (and a sharp cylinder rasterizes in closed form).
EnvelopeOptions nominal_solid() {
  EnvelopeOptions o;
  o.include_margin = false;
  return o;
}

/// The body's underside at any point, for sub-cell coverage at its footprint's edges.
class ShapeProbe final : public terrain::SurfaceProbe {
 public:
  ShapeProbe(EnvelopeRasterizer& rasterizer, const btCollisionShape& shape, const btTransform& pose)
      : rasterizer_(&rasterizer), shape_(&shape), pose_(pose) {}
  [[nodiscard]] double lower_at(double x, double y) const override {
    return rasterizer_->lower_at(*shape_, pose_, x, y);
  }

 private:
  EnvelopeRasterizer* rasterizer_;
  const btCollisionShape* shape_;
  btTransform pose_;
};

/// Refuses a shape that covers no area seen from below (a zero-size box or ball): a point
/// or a line cannot bear on soil.
void check_has_area(const btCollisionShape& shape) {
  btVector3 lo, hi;
  shape.getAabb(btTransform::getIdentity(), lo, hi);
  const btVector3 size = hi - lo;
  const double extent = std::max({double(size.x()), double(size.y()), double(size.z())});
  EnvelopeRaster probe;
  const int covered = extent > 0.0
                          ? rasterize_envelope(shape, btTransform::getIdentity(),
                                               EnvelopeGrid{lo.x(), lo.y(), extent / 64.0}, nominal_solid(), probe)
                          : 0;
  if (covered == 0)
    throw InvalidSetting(std::string("bullet.TerrainCoupling.add_body(body) shape ") + shape.getName(),
                         "no size seen from below",
                         "must cover some area (a zero-size box, ball or line cannot bear on soil)");
}

soil_detail::RigidBody solver_body(const btRigidBody& body) {
  soil_detail::RigidBody rb;
  rb.v = to_vec3(body.getLinearVelocity());
  rb.w = to_vec3(body.getAngularVelocity());
  rb.com = to_vec3(body.getCenterOfMassPosition());
  rb.inv_mass = body.getInvMass();
  const btMatrix3x3& inv = body.getInvInertiaTensorWorld();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) rb.inv_inertia[r][c] = inv[r][c];
  return rb;
}

/// A moving body's imprint: its envelope, and for spray its motion (after the soil's push),
/// pose and key. The key is the body's broadphase proxy id, given in the order bodies
/// joined the world, so it does not depend on the order of add_body.
terrain::Imprint moving_imprint(const EnvelopeRaster& envelope, const btRigidBody& body, bool spray) {
  terrain::Imprint im{&envelope};
  const btVector3 v = body.getLinearVelocity(), w = body.getAngularVelocity(), c = body.getCenterOfMassPosition();
  const btQuaternion q = body.getOrientation();
  im.velocity = {v.x(), v.y(), v.z()}, im.angular_velocity = {w.x(), w.y(), w.z()};
  im.centre = {c.x(), c.y(), c.z()};
  im.orientation = {q.w(), q.x(), q.y(), q.z()};
  const btBroadphaseProxy* proxy = body.getBroadphaseHandle();
  im.body = proxy ? static_cast<std::uint64_t>(proxy->m_uniqueId) : 0;
  im.spray = spray && proxy != nullptr;  // a body outside the world has no stable key: it does not spray
  return im;
}

/// A column's carried pressure before it has one (BodyContact::carried).
constexpr double kNoMemory = std::numeric_limits<double>::infinity();
/// Elements whose stiffness lies below this unload elastically (ContactElement::stiffness).
constexpr double kUnloading = std::numeric_limits<double>::infinity();

bool same_window(const GridRect& from, const EnvelopeRaster& to) {
  return from.i0 == to.i0 && from.j0 == to.j0 && from.nx == to.nx && from.ny == to.ny;
}

/// Values kept per envelope column, moved from the old window to the new one (`fresh` where
/// new). The same window keeps them as they are; otherwise each row's overlap is copied at once.
template <class T>
void remap(std::vector<T>& values, const GridRect& from, const EnvelopeRaster& to, T fresh = T{}) {
  if (same_window(from, to) && values.size() == to.lower.size()) return;
  std::vector<T> moved(to.lower.size(), fresh);
  if (!values.empty()) {
    // Columns x of the new window whose old column i = to.i0 + x - from.i0 lies in [0, from.nx).
    const std::int64_t x0 = std::max<std::int64_t>(0, from.i0 - to.i0);
    const std::int64_t x1 = std::min<std::int64_t>(to.nx, from.i0 + from.nx - to.i0);
    for (int y = 0; y < to.ny && x0 < x1; ++y) {
      const std::int64_t j = to.j0 + y - from.j0;
      if (j < 0 || j >= from.ny) continue;
      const auto src = values.begin() + static_cast<std::ptrdiff_t>(j * from.nx + (to.i0 + x0 - from.i0));
      std::copy(src, src + (x1 - x0), moved.begin() + static_cast<std::ptrdiff_t>(std::int64_t{y} * to.nx + x0));
    }
  }
  values.swap(moved);
}

/// Raster indices of the old window moved to the new one (those that left it dropped), as
/// remap moves the values they point at.
void remap_indices(std::vector<std::uint32_t>& indices, const GridRect& from, const EnvelopeRaster& to) {
  if (same_window(from, to)) return;
  std::size_t kept = 0;
  for (const std::uint32_t k : indices) {
    const std::int64_t i = from.i0 + k % static_cast<std::uint32_t>(from.nx);
    const std::int64_t j = from.j0 + k / static_cast<std::uint32_t>(from.nx);
    if (to.contains(i, j)) indices[kept++] = static_cast<std::uint32_t>(to.index(i, j));
  }
  indices.resize(kept);
}
}  // namespace

/// What a body's soil contact keeps between substeps.
struct TerrainCoupling::BodyContact {
  terrain::ContactPatch patch;
  std::vector<soil_detail::Block> blocks, previous;  // this substep's and the last one's (warm start)
  // Per envelope column, m: the shear displacement (the slip along the surface accumulated
  // as a vector while the column is in contact; Janosi-Hanamoto's j is its length, which
  // also remoulds the soil, terrain::shear::remoulding). As a vector, slip that reverses
  // undoes itself.
  std::vector<Vec3> shear;
  std::vector<double> shear_length;  // |shear|: the soil's and the blocks' input
  // Per envelope column, Pa: what the column pushed with at the end of the last substep while
  // it unloaded elastically (+infinity: no memory; it was pressed, or out of contact). Wong's
  // unloading starts from the pressure a column carried: soil laid under a body by erosion
  // raises the column's top, and with it the elastic line, without loading it; the memory
  // keeps that soil from pushing until the body presses it (without it a sphere dropped into
  // sand climbed back out of its crater by 20 %: docs/terrain.md, "Unloading").
  std::vector<double> carried;
  // The raster indices whose shear or carried value may differ from fresh (zero, no memory):
  // the columns touched last substep, remapped with the window. A substep clears just these
  // instead of refilling arrays the window's size (a wheel's window is 3 times its patch).
  // kept_valid false (a restored state): unknown, so the next substep refills.
  std::vector<std::uint32_t> kept;
  bool kept_valid = false;
  // Scratch of advance_memory: this substep's new values, by raster index, in element order.
  std::vector<std::pair<std::uint32_t, Vec3>> new_shear;
  std::vector<std::pair<std::uint32_t, double>> new_carried;
  SoilForce last;
  bool resting = false;  // the body was at rest: its blocks and patch still hold it
  // m: how far the blocks' points have moved with the body since the blocks were built (a
  // bound: the sum of each substep's largest move), for follow_drift.
  double drift = 0.0;
  // The body's velocities at the end of the last substep (the start of this one).
  btVector3 v_end{0, 0, 0}, w_end{0, 0, 0};
  bool has_end = false;
};

void TerrainCoupling::save_contact(const BodyContact& c, ByteWriter& w) {
  w.put_array(c.patch.elements);
  w.put(c.patch.patch_width), w.put(c.patch.area), w.put(c.patch.touching_columns);
  w.put_array(c.blocks), w.put_array(c.previous), w.put_array(c.shear), w.put_array(c.shear_length);
  w.put_array(c.carried);
  coupling_detail::put_vector(w, c.last.force), coupling_detail::put_vector(w, c.last.torque);
  coupling_detail::put_vector(w, c.last.normal_force);
  w.put(c.last.contact_columns), w.put(static_cast<std::uint8_t>(c.last.yielded));
  coupling_detail::put_vector(w, c.v_end), coupling_detail::put_vector(w, c.w_end);
  w.put(static_cast<std::uint8_t>(c.resting)), w.put(static_cast<std::uint8_t>(c.has_end));
  w.put(c.drift);
}

void TerrainCoupling::restore_contact(ByteReader& r, BodyContact& c, std::size_t envelope_columns,
                                      std::uint32_t version) {
  // Version 1 elements and blocks end before the unloading spring's fields: they read as
  // rigid ones, which they were. Versions 2 to 4 end before the rates of following
  // (follow_drift): they read with none, and the next substep builds the contact afresh.
  constexpr std::size_t kElementV1 = offsetof(terrain::ContactElement, stiffness);
  constexpr std::size_t kBlockV1 = offsetof(soil_detail::Block, stiffness);
  constexpr std::size_t kElementV4 = offsetof(terrain::ContactElement, pressure_rate);
  constexpr std::size_t kBlockV4 = offsetof(soil_detail::Block, capacity_rate);
  if (version >= 5)
    coupling_detail::get_any_array(r, c.patch.elements, "contact patch");
  else if (version >= 2)
    coupling_detail::get_prefix_array<terrain::ContactElement, kElementV4>(r, c.patch.elements, "contact patch");
  else
    coupling_detail::get_prefix_array<terrain::ContactElement, kElementV1>(r, c.patch.elements, "contact patch");
  c.patch.patch_width = r.get<double>("contact patch"), c.patch.area = r.get<double>("contact patch");
  c.patch.touching_columns = r.get<int>("contact patch");
  for (auto* blocks : {&c.blocks, &c.previous})
    if (version >= 5)
      coupling_detail::get_any_array(r, *blocks, "contact blocks");
    else if (version >= 2)
      coupling_detail::get_prefix_array<soil_detail::Block, kBlockV4>(r, *blocks, "contact blocks");
    else
      coupling_detail::get_prefix_array<soil_detail::Block, kBlockV1>(r, *blocks, "contact blocks");
  coupling_detail::get_any_array(r, c.shear, "shear displacement");
  r.get_array(c.shear_length, c.shear.size(), "shear displacement");
  if (version >= 3)
    coupling_detail::get_any_array(r, c.carried, "carried pressure");
  else
    c.carried.clear();  // no memory: the columns unload from their yield line, as they did
  c.last.force = coupling_detail::get_vector(r, "soil force"),
  c.last.torque = coupling_detail::get_vector(r, "soil force");
  c.last.normal_force = coupling_detail::get_vector(r, "soil force");
  c.last.contact_columns = r.get<int>("soil force"), c.last.yielded = r.get<std::uint8_t>("soil force") != 0;
  c.v_end = coupling_detail::get_vector(r, "contact velocities"),
  c.w_end = coupling_detail::get_vector(r, "contact velocities");
  c.resting = r.get<std::uint8_t>("contact flags") != 0, c.has_end = r.get<std::uint8_t>("contact flags") != 0;
  c.drift = version >= 5 ? r.get<double>("contact drift") : 0.0;
  c.kept.clear(), c.kept_valid = false;
  check_contact(r, c, envelope_columns);
}

// What the next substeps index or divide by must be sound: a corrupt state is refused,
// never read out of bounds or turned into NaN.
void TerrainCoupling::check_contact(const ByteReader& r, const BodyContact& c, std::size_t envelope_columns) {
  if (!c.shear.empty() && c.shear.size() != envelope_columns)
    r.fail("shear displacement of " + std::to_string(c.shear.size()) + " columns, the envelope has " +
           std::to_string(envelope_columns));
  if (!c.carried.empty() && c.carried.size() != envelope_columns)
    r.fail("carried pressure of " + std::to_string(c.carried.size()) + " columns, the envelope has " +
           std::to_string(envelope_columns));
  for (const double p : c.carried)
    if (!(p >= 0.0)) r.fail("a carried pressure of " + detail::to_text(p) + " Pa (must be >= 0 or +infinity)");
  bool sound = coupling_detail::finite(c.last.force) && coupling_detail::finite(c.last.torque) &&
               coupling_detail::finite(c.v_end) && coupling_detail::finite(c.w_end);
  for (const terrain::ContactElement& e : c.patch.elements)
    sound = sound && e.raster_index < static_cast<std::int64_t>(envelope_columns) && finite(e.point) &&
            finite(e.normal) && std::isfinite(e.area) && !std::isnan(e.pressure) && e.stiffness >= 0.0 &&
            e.preload >= 0.0 && std::isfinite(e.preload) && e.pressure_rate >= 0.0 && std::isfinite(e.pressure_rate);
  for (const auto* blocks : {&c.blocks, &c.previous})
    for (const soil_detail::Block& b : *blocks)
      sound =
          sound && finite(b.point) && finite(b.normal) && !std::isnan(b.capacity) && b.stiffness >= 0.0 &&
          b.preload >= 0.0 && std::isfinite(b.preload) &&
          std::isfinite(b.cohesion + b.mobilised + b.normal_impulse + b.t1_impulse + b.t2_impulse + b.mass_n +
                        b.mass_t1 + b.mass_t2) &&
          std::isfinite(b.t1.x + b.t1.y + b.t1.z + b.t2.x + b.t2.y + b.t2.z + b.start_n + b.start_t1 + b.start_t2) &&
          b.capacity_rate >= 0.0 && std::isfinite(b.capacity_rate + b.approach + b.deepest);
  for (std::size_t k = 0; k < c.shear.size(); ++k)
    sound = sound && std::isfinite(c.shear[k].x + c.shear[k].y + c.shear[k].z + c.shear_length[k]);
  sound = sound && c.drift >= 0.0 && std::isfinite(c.drift);
  if (!sound) r.fail("the soil contact's state holds a non-finite value or an index beyond the envelope");
}

TerrainCoupling::Body::Body() : contact(std::make_unique<BodyContact>()) {}
TerrainCoupling::Body::~Body() = default;
TerrainCoupling::Body::Body(Body&&) noexcept = default;
TerrainCoupling::Body& TerrainCoupling::Body::operator=(Body&&) noexcept = default;

void SoilContactSettings::validate() const {
  const Check c{"bullet.SoilContactSettings"};
  c.in_closed("block_columns", block_columns, 1, 64);
  c.in_closed("iterations", iterations, 1, 1000);
  c.in_closed("resting_iterations", resting_iterations, 1, 1000);
  c.in_closed("follow_drift", follow_drift, 0.0, 2.0);
  c.non_negative("follow_speed", follow_speed);
}

void BodySoilSettings::validate() const {
  const Check c{"bullet.BodySoilSettings"};
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
  c.in_closed("soil_interval", soil_interval, 0.0, 0.125);
}

TerrainCoupling::TerrainCoupling(btDiscreteDynamicsWorld& world, terrain::Terrain& soil,
                                 TerrainCouplingSettings settings)
    : world_(world),
      soil_(soil),
      settings_(std::move(settings)),
      tiles_(world, soil, settings_.tiles),
      rasterizer_(EnvelopeGrid{soil.settings().origin_x, soil.settings().origin_y, soil.settings().cell},
                  nominal_solid()) {
  settings_.validate();
  tiles_.set_region(settings_.region);
  rigid_ = soil.settings().material.rigid;
  tiles_.set_collision_group(rigid_ ? int(btBroadphaseProxy::StaticFilter) : settings_.soil_filter_bit);
  world_.addAction(this);
  Directory::enter(&world_, this);
}

TerrainCoupling::~TerrainCoupling() { detach(); }

bool TerrainCoupling::holds(const btRigidBody* body) const {
  return std::any_of(bodies_.begin(), bodies_.end(), [body](const Body& b) { return b.body == body; });
}

void TerrainCoupling::refuse_overlapping_coupling(const btRigidBody& body) const {
  Directory::for_each_other(&world_, this, [&](const TerrainCoupling& other) {
    if (!other.holds(&body) || !other.settings_.region.overlaps(settings_.region)) return;
    throw InvalidSetting("bullet.TerrainCoupling.add_body(body)",
                         coupling_detail::body_text(body) +
                             ", already in another TerrainCoupling of this world whose region " +
                             coupling_detail::region_text(other.settings_.region) + " overlaps this one's " +
                             coupling_detail::region_text(settings_.region),
                         "a body may be in several terrain couplings only if their regions are disjoint (else "
                         "both soils would push it): remove_body it from the other first, or give the couplings "
                         "disjoint regions");
  });
}

void TerrainCoupling::detach() {
  if (detached_) return;
  const std::vector<const void*> held = coupling_detail::bodies_held_by(world_);
  for (const Body& b : bodies_)  // restore Bullet's tile contact of the bodies still in the world
    if (coupling_detail::holds(held, b.body) && b.body->getBroadphaseHandle() != nullptr)
      b.body->getBroadphaseHandle()->m_collisionFilterMask |= settings_.soil_filter_bit;
  bodies_.clear();
  imprints_.clear();
  tiles_.remove_all();
  world_.removeAction(this);
  Directory::leave(this);
  detached_ = true;
}

void TerrainCoupling::add_body(btRigidBody* body, BodySoilSettings body_settings) {
  if (body == nullptr) throw InvalidSetting("bullet.TerrainCoupling.add_body(body)", "null", "must be a rigid body");
  if (detached_)
    throw InvalidSetting("bullet.TerrainCoupling.add_body(body)", "after detach()",
                         "a detached coupling takes no bodies: make a new one");
  body_settings.validate();
  refuse_overlapping_coupling(*body);
  Body b;
  b.body = body;
  b.settings = body_settings;
  b.shape = body->getCollisionShape();
  if (b.shape != nullptr) b.scaling = b.shape->getLocalScaling();
  b.seen_in_world = body->getBroadphaseHandle() != nullptr;
  if (body_settings.deform) {  // once: then rasterizing it never fails for a sane pose
    b.reach = check_rasterizable(*body->getCollisionShape(), rasterizer_.grid().cell, rasterizer_.options());
    check_has_area(*body->getCollisionShape());
  }
  remove_body(body);
  if (body_settings.enable_ccd && !body->isStaticOrKinematicObject()) {
    btVector3 lo, hi;
    body->getCollisionShape()->getAabb(btTransform::getIdentity(), lo, hi);
    const btVector3 size = hi - lo;
    const btScalar thinnest = size[size.minAxis()];
    body->setCcdMotionThreshold(btScalar(body_settings.ccd_motion_share) * thinnest);
    body->setCcdSweptSphereRadius(btScalar(body_settings.ccd_sphere_share) * thinnest);
  }
  if (!rigid_ && !body->isStaticOrKinematicObject() && body_settings.deform) {
    // Shore owns this body's contact with soft soil: Bullet must not collide it with the tiles.
    btBroadphaseProxy* proxy = body->getBroadphaseHandle();
    if (proxy == nullptr)
      throw InvalidSetting("bullet.TerrainCoupling.add_body(body)", "not in the world",
                           "add the body to the dynamics world before add_body");
    proxy->m_collisionFilterMask &= ~settings_.soil_filter_bit;
    drop_tile_pairs(proxy);
  }
  if (body_is_sane(*body) && body_settings.deform && can_rasterize(b)) rasterize(b);
  bodies_.push_back(std::move(b));
  if (body_is_sane(*body)) {
    btVector3 lo, hi;
    body->getCollisionShape()->getAabb(body->getWorldTransform(), lo, hi);
    const double m = settings_.cover_margin;
    tiles_.ensure_cover(lo.x() - m, lo.y() - m, hi.x() + m, hi.y() + m);
  }
}

void TerrainCoupling::remove_body(btRigidBody* body) {
  for (const Body& b : bodies_)
    if (b.body == body && body->getBroadphaseHandle() != nullptr)
      body->getBroadphaseHandle()->m_collisionFilterMask |= settings_.soil_filter_bit;
  std::erase_if(bodies_, [body](const Body& b) { return b.body == body; });
}

bool TerrainCoupling::body_is_sane(const btRigidBody& body) const {
  return coupling_detail::body_is_sane(body, settings_.max_speed);
}

bool TerrainCoupling::shape_still_fits(Body& b) const {
  const btCollisionShape* shape = b.body->getCollisionShape();
  if (shape == b.shape && (shape == nullptr || shape->getLocalScaling() == b.scaling)) return b.shape_fits;
  b.shape = shape;
  b.scaling = shape ? shape->getLocalScaling() : btVector3(1, 1, 1);
  b.envelope.lower.clear();  // made for the old shape
  b.shape_fits = false;
  if (shape == nullptr) return false;
  try {
    b.reach = check_rasterizable(*shape, rasterizer_.grid().cell, rasterizer_.options());
    check_has_area(*shape);
    b.shape_fits = true;
  } catch (const InvalidSetting&) {
    // Skipped (and counted) while the soil cannot take the shape.
  }
  return b.shape_fits;
}

void TerrainCoupling::own_tile_contact(Body& b) {
  btBroadphaseProxy* proxy = b.body->getBroadphaseHandle();
  if (rigid_ || proxy == nullptr || b.body->isStaticOrKinematicObject()) return;
  if ((proxy->m_collisionFilterMask & settings_.soil_filter_bit) == 0) return;
  proxy->m_collisionFilterMask &= ~settings_.soil_filter_bit;
  drop_tile_pairs(proxy);
}

bool TerrainCoupling::can_rasterize(const Body& b) const {
  return pose_rasterizable(b.body->getWorldTransform(), b.reach, rasterizer_.grid());
}

void TerrainCoupling::cover_bodies(double substep) {
  const double margin = settings_.cover_margin;
  auto cover = [&](const btRigidBody& body) {
    if (body.isStaticObject() || !body_is_sane(body)) return;
    btVector3 lo, hi;
    body.getCollisionShape()->getAabb(body.getWorldTransform(), lo, hi);
    const double reach = margin + 2.0 * substep * body.getLinearVelocity().length();
    tiles_.ensure_cover(lo.x() - reach, lo.y() - reach, hi.x() + reach, hi.y() + reach);
  };
  if (settings_.cover_all_bodies) {
    const btCollisionObjectArray& objects = world_.getCollisionObjectArray();
    for (int k = 0; k < objects.size(); ++k)
      if (const btRigidBody* body = btRigidBody::upcast(objects[k])) cover(*body);
  } else {
    for (const Body& b : bodies_) cover(*b.body);
  }
}

void TerrainCoupling::drop_tile_pairs(btBroadphaseProxy* proxy) {
  // Pairs the body already has with soil tiles (made for earlier bodies) would keep Bullet's
  // rigid contact alive; its pairs with other bodies stay.
  btOverlappingPairCache* cache = world_.getBroadphase()->getOverlappingPairCache();
  btBroadphasePairArray& pairs = cache->getOverlappingPairArray();
  std::vector<std::pair<btBroadphaseProxy*, btBroadphaseProxy*>> doomed;
  for (int k = 0; k < pairs.size(); ++k) {
    btBroadphaseProxy* a = pairs[k].m_pProxy0;
    btBroadphaseProxy* b = pairs[k].m_pProxy1;
    if (a != proxy && b != proxy) continue;
    const btBroadphaseProxy* other = a == proxy ? b : a;
    if (tiles_.is_tile(static_cast<const btCollisionObject*>(other->m_clientObject))) doomed.emplace_back(a, b);
  }
  for (const auto& [a, b] : doomed) cache->removeOverlappingPair(a, b, world_.getDispatcher());
}

bool TerrainCoupling::overlaps_region(const btRigidBody& body) const {
  const Region& r = settings_.region;
  btVector3 lo, hi;
  body.getCollisionShape()->getAabb(body.getWorldTransform(), lo, hi);
  const double pad = soil_.settings().cell;
  return hi.x() + pad >= r.x0 && lo.x() - pad <= r.x1 && hi.y() + pad >= r.y0 && lo.y() - pad <= r.y1;
}

void TerrainCoupling::rasterize(Body& b) {
  const GridRect old{b.envelope.i0, b.envelope.j0, b.envelope.nx, b.envelope.ny};
  b.envelope_pose = b.body->getWorldTransform();
  rasterizer_.rasterize(*b.body->getCollisionShape(), b.envelope_pose, b.envelope);
  b.pressed = false;
  b.envelope_fresh = true;
  clip_to_region(b.envelope);
  BodyContact& c = *b.contact;
  remap(c.shear, old, b.envelope);
  remap(c.shear_length, old, b.envelope);
  remap(c.carried, old, b.envelope, kNoMemory);
  remap_indices(c.kept, old, b.envelope);
  b.contact->resting = false;
}

bool TerrainCoupling::drifted(const Body& b) const {
  // A tenth of a millimetre, a milliradian: well below what a column of soil resolves.
  const btTransform& now = b.body->getWorldTransform();
  const btTransform& then = b.envelope_pose;
  if ((now.getOrigin() - then.getOrigin()).length() > btScalar(1e-4)) return true;
  const btMatrix3x3 turn = now.getBasis() * then.getBasis().transpose();
  return std::abs(double(turn[0][1] - turn[1][0])) + std::abs(double(turn[0][2] - turn[2][0])) +
             std::abs(double(turn[1][2] - turn[2][1])) >
         2e-3;
}

SoilForce TerrainCoupling::soil_force(const btRigidBody* body) const {
  for (const Body& b : bodies_)
    if (b.body == body) return b.contact->last;
  return {};
}

void TerrainCoupling::clip_to_region(EnvelopeRaster& env) const {
  const Region& r = settings_.region;
  if (r.everywhere()) return;
  for (int b = 0; b < env.ny; ++b)
    for (int a = 0; a < env.nx; ++a)
      if (!r.contains(soil_.column_x(env.i0 + a), soil_.column_y(env.j0 + b)))
        env.lower[static_cast<std::size_t>(b) * static_cast<std::size_t>(env.nx) + static_cast<std::size_t>(a)] =
            EnvelopeRaster::kNoLower;
}

void TerrainCoupling::gather_contact(Body& b) {
  BodyContact& c = *b.contact;
  const ShapeProbe probe(rasterizer_, *b.body->getCollisionShape(), b.envelope_pose);
  soil_.contact(b.envelope, c.shear_length, settings_.contact.sub_cell_coverage ? &probe : nullptr, c.patch);
  b.envelope_fresh = false;
  c.drift = 0.0;
  limit_to_carried(b);
  std::swap(c.previous, c.blocks);
  soil_detail::gather_blocks(c.patch.elements, soil_.settings().material, c.shear_length,
                             settings_.contact.block_columns, c.blocks);
  soil_detail::warm_start(c.previous, c.blocks);
}

namespace {
/// The raster index of an element's own column (-1 for walls and for fringe elements, which
/// lie on the uncovered neighbour of the column whose index they carry).
std::int64_t own_column(const EnvelopeRaster& env, const terrain::ContactElement& e) {
  if (e.wall || e.raster_index < 0 || !env.contains(e.i, e.j)) return -1;
  const auto k = static_cast<std::int64_t>(env.index(e.i, e.j));
  return k == e.raster_index ? k : -1;
}
}  // namespace

// An unloading column pushes at most with what it carried at the end of the last substep.
void TerrainCoupling::limit_to_carried(Body& b) {
  BodyContact& c = *b.contact;
  if (c.carried.size() != b.envelope.lower.size()) return;
  for (terrain::ContactElement& e : c.patch.elements) {
    if (!(e.stiffness < kUnloading)) continue;
    const std::int64_t k = own_column(b.envelope, e);
    if (k >= 0) e.preload = std::min(e.preload, c.carried[static_cast<std::size_t>(k)]);
  }
}

// What each touching column keeps for the next substep. Its shear displacement grows by the
// slip of the body over it (a fringe element moves its covered column's, after the column's
// own); columns out of contact start from zero. An unloading column keeps what it pushes with
// at the end of the substep: its spring at the body's final approach speed over it, within
// [0, its yield pressure]; columns pressed or out of contact keep no memory.
void TerrainCoupling::advance_memory(Body& b, const soil_detail::RigidBody& rb, double h) {
  BodyContact& c = *b.contact;
  const EnvelopeRaster& env = b.envelope;
  const std::size_t size = env.lower.size();
  const bool had = c.shear.size() == size;
  // The new values first, from the old ones (nothing is cleared before all are read).
  c.new_shear.clear(), c.new_carried.clear();
  for (terrain::ContactElement& e : c.patch.elements) {
    if (e.wall || e.raster_index < 0 || !env.contains(e.i, e.j)) continue;
    const Vec3 n = e.normal;
    const Vec3 u = rb.point_velocity(e.point);
    const auto k = static_cast<std::uint32_t>(e.raster_index);
    const Vec3 slip = u - n * dot(u, n);
    c.new_shear.emplace_back(k, (had ? c.shear[k] : Vec3{}) + slip * h);
    if (!(e.stiffness < kUnloading)) continue;
    // The spring at the end of the substep: what the column carries on, and where a patch
    // kept for the next substep (follow_drift) starts from.
    e.preload = std::clamp(e.preload + e.stiffness * h * -dot(u, n), 0.0, e.pressure);
    if (env.index(e.i, e.j) == k) c.new_carried.emplace_back(k, e.preload);  // its own column (a fringe's is not)
  }
  // Back to fresh: only the entries kept last substep, when they are known; else all of them.
  const bool sparse = had && c.kept_valid;
  if (sparse) {
    for (const std::uint32_t k : c.kept) c.shear[k] = {}, c.shear_length[k] = 0.0;
  } else {
    c.shear.assign(size, {});
    c.shear_length.assign(size, 0.0);
  }
  if (c.new_carried.empty()) {
    c.carried.clear();
  } else if (sparse && c.carried.size() == size) {
    for (const std::uint32_t k : c.kept) c.carried[k] = kNoMemory;
  } else {
    c.carried.assign(size, kNoMemory);
  }
  c.kept.clear();
  for (const auto& [k, j] : c.new_shear) {
    c.shear[k] = j;
    c.shear_length[k] = std::sqrt(dot(j, j));
    c.kept.push_back(k);
  }
  for (const auto& [k, p] : c.new_carried) c.carried[k] = p;  // k is among the shear's
  c.kept_valid = true;
}

// A body at rest needs from the soil what it needed last substep: the same impulse cancels
// the same forces. If that leaves it moving slower than rest_speed and rest_spin, the soil
// holds it still (the little that is left over, it takes too) and nothing else is solved:
// a few dozen operations. If not (something pushed it), its kept contact is solved.
bool TerrainCoupling::hold_at_rest(Body& b, double h) {
  btRigidBody& body = *b.body;
  BodyContact& c = *b.contact;
  const btVector3 v0 = body.getLinearVelocity(), w0 = body.getAngularVelocity();
  const btVector3 v = v0 + c.last.force * btScalar(h * body.getInvMass());
  const btVector3 w = w0 + body.getInvInertiaTensorWorld() * (c.last.torque * btScalar(h));
  if (v.length() > btScalar(settings_.rest_speed) || w.length() > btScalar(settings_.rest_spin)) return false;
  // The soil's whole impulse this substep is the one that stops the body: m (0 - v0) and
  // I (0 - w0). More than last substep's (a load growing) is for the solve to bound by what
  // the soil bears.
  const btMatrix3x3 inertia = body.getInvInertiaTensorWorld().inverse();
  const btVector3 force = -v0 * btScalar(1.0 / (h * body.getInvMass()));
  if (force.length() > c.last.force.length() * btScalar(1.0 + 1e-6)) return false;
  c.last.force = force;
  c.last.torque = inertia * (-w0) * btScalar(1.0 / h);
  body.setLinearVelocity(btVector3(0, 0, 0));
  body.setAngularVelocity(btVector3(0, 0, 0));
  btTransform corrected;
  btTransformUtil::integrateTransform(body.getCenterOfMassTransform(), -v0, -w0, btScalar(h), corrected);
  body.setCenterOfMassTransform(corrected);
  return true;
}

bool TerrainCoupling::react(Body& b, double h) {
  btRigidBody& body = *b.body;
  BodyContact& c = *b.contact;
  if (body.getInvMass() <= 0.0 || b.envelope.lower.empty()) {
    c.last = {};
    return false;
  }
  if (c.resting && hold_at_rest(b, h)) {
    ++stats_.resting_bodies;
    return false;
  }
  c.last = {};
  // The soil where the body stood at the start of this substep (the envelope kept from the
  // end of the previous one): Bullet has since applied gravity and integrated freely, since
  // it does not collide this body with soft tiles. A body at rest keeps its last contact.
  // Kept since the substep before (no soil step, little drift): the contact moves with the body.
  const bool follow = !c.resting && !b.envelope_fresh && c.has_end;
  if (c.resting)
    ++stats_.resting_bodies;
  else if (!follow)
    gather_contact(b);
  if (c.blocks.empty()) return false;

  soil_detail::RigidBody rb = solver_body(body);
  soil_detail::RigidBody start = rb;
  if (c.has_end) start.v = to_vec3(c.v_end), start.w = to_vec3(c.w_end);
  if (follow) {
    c.drift += soil_detail::follow_body(c.blocks, start, h);
    ++stats_.contacts_followed;
  }

  const btVector3 v0 = body.getLinearVelocity(), w0 = body.getAngularVelocity();
  const soil_detail::SolverSettings solver{
      settings_.contact.block_columns, c.resting ? settings_.contact.resting_iterations : settings_.contact.iterations,
      c.resting};
  soil_detail::SolveResult r = soil_detail::solve(rb, start, c.blocks, soil_.settings().material, h, solver);
  if (r.stuck) stop_sway(body, rb, r);
  body.setLinearVelocity(to_bt(rb.v));
  body.setAngularVelocity(to_bt(rb.w));
  // Re-integrate this substep's pose with the corrected velocity.
  const btVector3 dv = body.getLinearVelocity() - v0, dw = body.getAngularVelocity() - w0;
  btTransform corrected;
  btTransformUtil::integrateTransform(body.getCenterOfMassTransform(), dv, dw, btScalar(h), corrected);
  body.setCenterOfMassTransform(corrected);

  stats_.plastic_work += r.work;
  stats_.shear_work += r.shear_work;
  if (r.yielded) ++stats_.yields;
  c.last.force = to_bt(r.impulse * (1.0 / h));
  c.last.torque = to_bt(r.angular_impulse * (1.0 / h));
  c.last.normal_force = to_bt(r.normal_impulse * (1.0 / h));
  c.last.contact_columns = c.patch.touching_columns;
  c.last.yielded = r.yielded;
  if (!c.resting) advance_memory(b, rb, h);
  return r.yielded;
}

// A body the soil holds that the solve leaves moving slower than rest_speed and rest_spin
// (unloading columns are springs: a settled body keeps swaying by far less than that) is
// stopped: the soil takes what is left, as hold_at_rest does. The next substep then needs the
// force this one ended with and hold_at_rest holds it; left swaying, it was solved every
// substep (5 times the cost of a held body).
void TerrainCoupling::stop_sway(const btRigidBody& body, soil_detail::RigidBody& rb,
                                soil_detail::SolveResult& r) const {
  const double speed = std::sqrt(dot(rb.v, rb.v)), spin = std::sqrt(dot(rb.w, rb.w));
  if (!(speed <= settings_.rest_speed && spin <= settings_.rest_spin) || !(rb.inv_mass > 0.0)) return;
  const btVector3 stop_spin = body.getInvInertiaTensorWorld().inverse() * (-to_bt(rb.w));
  r.impulse = r.impulse - rb.v * (1.0 / rb.inv_mass);
  r.angular_impulse = r.angular_impulse + Vec3{stop_spin.x(), stop_spin.y(), stop_spin.z()};
  rb.v = rb.w = {};
}

void TerrainCoupling::keep_above_bedrock(Body& b) {
  // A body driven below bedrock within one substep (a very fast impact) is lifted back.
  EnvelopeRaster& env = b.envelope;
  if (env.nx <= 0 || env.ny <= 0) return;
  base_scratch_.resize(env.lower.size());
  soil_.base_heights({env.i0, env.j0, env.nx, env.ny}, base_scratch_);
  const double soil_depth = soil_.settings().material.soil_depth;
  double depth = 0.0;
  for (std::size_t k = 0; k < env.lower.size(); ++k)
    if (env.covers(k)) depth = std::max(depth, base_scratch_[k] - soil_depth - env.lower[k]);
  if (depth <= 0.0) return;
  btRigidBody& body = *b.body;
  btTransform t = body.getCenterOfMassTransform();
  t.setOrigin(t.getOrigin() + btVector3(0, 0, btScalar(depth)));
  body.setCenterOfMassTransform(t);
  btVector3 v = body.getLinearVelocity();
  v.setZ(std::max<btScalar>(v.z(), 0));
  body.setLinearVelocity(v);
  for (std::size_t k = 0; k < env.lower.size(); ++k)
    if (env.covers(k)) env.lower[k] += depth;
  ++stats_.rescues;
}

void TerrainCoupling::wake_bodies_over(const std::vector<GridRect>& changed) {
  // Soft-soil bodies have no Bullet contact with the tiles, so nothing else wakes them; a
  // body at rest over soil that changed (the ring around its envelope too: walls) gathers
  // its contact afresh.
  for (Body& b : bodies_) {
    if (b.envelope.lower.empty()) continue;
    const EnvelopeRaster& e = b.envelope;
    for (const GridRect& r : changed)
      if (r.i0 <= e.i0 + e.nx && e.i0 <= r.i0 + r.nx && r.j0 <= e.j0 + e.ny && e.j0 <= r.j0 + r.ny) {
        if (!b.body->isActive()) b.body->activate(true);
        b.contact->resting = false;
        b.envelope_fresh = true;  // its contact is gathered again from the changed soil
        break;
      }
  }
}

void TerrainCoupling::rescue_fallen_bodies() {
  for (Body& b : bodies_) {
    btRigidBody& body = *b.body;
    if (body.isStaticOrKinematicObject() || !body_is_sane(body)) continue;
    btVector3 lo, hi;
    body.getCollisionShape()->getAabb(body.getWorldTransform(), lo, hi);
    const btVector3 c = body.getCenterOfMassPosition();
    if (!settings_.region.contains(c.x(), c.y())) continue;
    const std::int64_t i = soil_.column_i(c.x()), j = soil_.column_j(c.y());
    if (lo.z() >= soil_.bedrock(i, j) - 0.01) continue;
    btTransform t = body.getWorldTransform();
    t.setOrigin(t.getOrigin() + btVector3(0, 0, btScalar(soil_.height(i, j) - lo.z())));
    body.setCenterOfMassTransform(t);
    btVector3 v = body.getLinearVelocity();
    v.setZ(std::max<btScalar>(v.z(), 0));
    body.setLinearVelocity(v);
    body.activate(true);
    ++stats_.rescues;
  }
}

bool TerrainCoupling::needs_envelope(const Body& b, double substep) const {
  const BodyContact& c = *b.contact;
  const double tolerance = settings_.contact.follow_drift * soil_.settings().cell;
  if (c.blocks.empty() || !(tolerance > 0.0)) return true;
  if (!(double(b.body->getLinearVelocity().length()) >= settings_.contact.follow_speed)) return true;
  // Where its contact will have moved by the next substep's solve.
  return c.drift + soil_detail::largest_point_speed(c.blocks, solver_body(*b.body)) * substep > tolerance;
}

bool TerrainCoupling::soil_due(double substep) {
  // The whole number of substeps nearest to the interval (at least one): at 1/240 s and the
  // default 1/120 s, every second substep. Counted, not timed, so no rounding of summed
  // substeps can skip or add a soil step.
  const double per_step = std::floor(settings_.soil_interval / substep + 0.5);
  ++substeps_since_soil_;
  time_since_soil_ += substep;
  return static_cast<double>(substeps_since_soil_) >= per_step;
}

void TerrainCoupling::step_soil() {
  const auto t0 = Clock::now();
  const terrain::StepReport report = soil_.step(imprints_, time_since_soil_);
  substeps_since_soil_ = 0;
  time_since_soil_ = 0.0;
  ++stats_.soil_steps;
  for (Body& b : bodies_) b.pressed = true;
  stats_.active_columns = report.active_columns;
  stats_.erosion_passes = report.erosion_passes;
  stats_.terrain_seconds += seconds_since(t0);
}

void TerrainCoupling::updateAction(btCollisionWorld*, btScalar substep) {
  const double h = substep;
  ++stats_.substeps;
  stats_.envelope_seconds = stats_.terrain_seconds = stats_.push_seconds = stats_.reaction_seconds = 0.0;
  stats_.resting_bodies = 0;
  // First: nothing below may read a body the world no longer holds.
  stats_.lost_bodies += coupling_detail::forget_bodies_out_of(world_, bodies_, [](Body& b) -> Body& { return b; });
  auto t0 = Clock::now();
  cover_bodies(h);
  stats_.push_seconds += seconds_since(t0);

  imprints_.clear();
  const bool soil_steps = soil_due(h);
  for (Body& b : bodies_) {
    btRigidBody& body = *b.body;
    if (!body_is_sane(body) || (b.settings.deform && !shape_still_fits(b))) {
      ++stats_.skipped_bodies;
      continue;
    }
    if (!b.settings.deform) continue;
    own_tile_contact(b);
    if (!overlaps_region(body)) {  // nothing to do here (another soil's region, say)
      b.envelope.lower.clear();
      continue;
    }
    bool moved = true;
    if (!body.isStaticOrKinematicObject() && body.isActive() && !rigid_) {
      t0 = Clock::now();
      react(b, h);  // reads the envelope of the previous substep
      stats_.reaction_seconds += seconds_since(t0);
      // A body the soil holds at rest presses nothing new: imprinting it again would only
      // re-press soil that erosion slid back under its sides, inflating sinkage forever. One
      // that creeps away from where it was imprinted is imprinted again.
      moved = b.envelope.lower.empty() || body.getLinearVelocity().length() > settings_.rest_speed ||
              body.getAngularVelocity().length() > settings_.rest_spin || drifted(b);
    }
    if (!body.isActive() || !moved) {
      // At rest its last envelope holds the soil it touches: slopes still eroding next to
      // it cannot slide under it. It presses nothing and activates no soil by itself, and
      // keeps its contact for the next substep.
      b.contact->resting = !b.envelope.lower.empty();
      if (b.pressed && !b.envelope.lower.empty()) {
        terrain::Imprint hold{&b.envelope};
        hold.hold = true;
        imprints_.push_back(hold);
      } else if (!b.envelope.lower.empty()) {  // made since the soil's last step: pressed once
        imprints_.push_back(moving_imprint(b.envelope, body, b.settings.spray));
      }
      continue;
    }
    // Between soil steps a body whose contact can follow it needs no new envelope.
    if (!soil_steps && !needs_envelope(b, h)) continue;
    if (!can_rasterize(b)) {  // a pose the envelope cannot take (not a rotation, say): skip, never poison the grid
      ++stats_.skipped_bodies;
      b.envelope.lower.clear();
      continue;
    }
    t0 = Clock::now();
    rasterize(b);  // at the (corrected) pose: this substep's imprint, next substep's bearing
    stats_.envelope_seconds += seconds_since(t0);
    if (!body.isStaticOrKinematicObject() && !rigid_) keep_above_bedrock(b);
    imprints_.push_back(moving_imprint(b.envelope, body, b.settings.spray));
  }

  stats_.active_columns = stats_.erosion_passes = 0;
  if (soil_steps) step_soil();

  t0 = Clock::now();
  const std::vector<GridRect> changed = soil_.take_changed();
  stats_.vertices_pushed += tiles_.push(changed);
  wake_bodies_over(changed);
  if (settings_.rescue_fallthrough) rescue_fallen_bodies();
  stats_.push_seconds += seconds_since(t0);
  for (Body& b : bodies_) {  // the start of the next substep, for the soil's work
    b.contact->v_end = b.body->getLinearVelocity();
    b.contact->w_end = b.body->getAngularVelocity();
    b.contact->has_end = true;
  }
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
