#include "shore/bullet/terrain_coupling.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>
#include <vector>

#include <BulletCollision/BroadphaseCollision/btDispatcher.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <LinearMath/btTransformUtil.h>

#include "coupling_util.h"
#include "shore/bullet/envelope.h"
#include "shore/core/error.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

namespace {
using coupling_detail::Clock;
using coupling_detail::seconds_since;

/// The body's true shape, without Bullet's collision margin: Shore, not Bullet, makes the
/// contact of added bodies with soft soil (and a sharp cylinder rasterizes in closed form).
EnvelopeOptions nominal_solid() {
  EnvelopeOptions o;
  o.include_margin = false;
  return o;
}
}  // namespace

void BodySoilSettings::validate() const {
  const Check c{"bullet.BodySoilSettings"};
  c.in_left_open("ccd_motion_share", ccd_motion_share, 0.0, 1.0);
  c.in_left_open("ccd_sphere_share", ccd_sphere_share, 0.0, 1.0);
}

void TerrainCouplingSettings::validate() const {
  tiles.validate();
  const Check c{"bullet.TerrainCouplingSettings"};
  c.positive("cover_margin", cover_margin);
  c.positive("max_speed", max_speed);
  c.positive("rest_speed", rest_speed);
  c.positive("rest_spin", rest_spin);
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
}

TerrainCoupling::~TerrainCoupling() { world_.removeAction(this); }

void TerrainCoupling::add_body(btRigidBody* body, BodySoilSettings body_settings) {
  if (body == nullptr) throw InvalidSetting("bullet.TerrainCoupling.add_body(body)", "null", "must be a rigid body");
  body_settings.validate();
  Body b;
  b.body = body;
  b.settings = body_settings;
  if (body_settings.deform)  // once: then rasterizing it never fails for a sane pose
    b.reach = check_rasterizable(*body->getCollisionShape(), rasterizer_.grid().cell, rasterizer_.options());
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
  rasterizer_.rasterize(*b.body->getCollisionShape(), b.body->getWorldTransform(), b.envelope);
  clip_to_region(b.envelope);
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

bool TerrainCoupling::react(Body& b, double h) {
  btRigidBody& body = *b.body;
  const double inv_mass = body.getInvMass();
  if (inv_mass <= 0.0 || b.envelope.lower.empty()) return false;
  const double mass = 1.0 / inv_mass;
  const btVector3 com = body.getCenterOfMassPosition();

  // The soil's state where the body stood at the start of this substep (the envelope kept
  // from the end of the previous one): Bullet has since applied gravity and integrated
  // freely, since it does not collide this body with soft tiles.
  const double p = -mass * double(body.getLinearVelocity().z());  // downward momentum to absorb
  const terrain::Bearing bearing = soil_.bearing(b.envelope, 0.0);
  if (bearing.contact_columns == 0 || p <= 0.0) return false;
  const double absorbable = bearing.capacity * h;  // +inf on bedrock
  const bool yields = p > absorbable;
  const double soil_impulse = yields ? absorbable : p;

  const btVector3 v0 = body.getLinearVelocity(), w0 = body.getAngularVelocity();
  const btVector3 patch = apply_soil_impulse(b, bearing, soil_impulse, com);
  apply_friction(body, patch - com, soil_impulse);

  // Re-integrate this substep's pose with the corrected velocity.
  const btVector3 dv = body.getLinearVelocity() - v0, dw = body.getAngularVelocity() - w0;
  btTransform corrected;
  btTransformUtil::integrateTransform(body.getCenterOfMassTransform(), dv, dw, btScalar(h), corrected);
  body.setCenterOfMassTransform(corrected);

  if (yields) {
    stats_.plastic_work += soil_impulse * std::max(0.0, -double(body.getLinearVelocity().z()));
    ++stats_.yields;
  }
  return yields;
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

btVector3 TerrainCoupling::apply_soil_impulse(Body& b, const terrain::Bearing& bearing, double impulse,
                                              const btVector3& com) {
  // Each contact column pushes up in proportion to the force it bears. Vertical impulses
  // at many points add up exactly to their sum at their weighted centre (same linear and
  // angular impulse), so one impulse is applied there: the bearing centre, not the centre
  // of mass (rigid-ground style impulses through the middle make boxes rock).
  // Columns on bedrock carry everything (infinite force): they share it equally; on fresh
  // soil (no capacity yet) the plain centre of the patch is used.
  const EnvelopeRaster& env = b.envelope;
  const bool on_bedrock = !std::isfinite(bearing.capacity);
  double weight = 0.0, cx = 0.0, cy = 0.0, cz = 0.0;
  for (const terrain::ColumnForce& c : bearing.columns) {
    const double w = on_bedrock ? (std::isfinite(c.force) ? 0.0 : 1.0) : (bearing.capacity > 0.0 ? c.force : 1.0);
    if (w <= 0.0) continue;
    const double z = env.contains(c.i, c.j) ? env.lower[env.index(c.i, c.j)] : double(com.z());
    cx += w * soil_.column_x(c.i);
    cy += w * soil_.column_y(c.j);
    cz += w * z;
    weight += w;
  }
  if (weight <= 0.0) return com;
  const btVector3 centre(btScalar(cx / weight), btScalar(cy / weight), btScalar(cz / weight));
  if (impulse > 0.0) b.body->applyImpulse(btVector3(0, 0, btScalar(impulse)), centre - com);
  return centre;
}

void TerrainCoupling::apply_friction(btRigidBody& body, const btVector3& arm, double normal_impulse) {
  // One Coulomb contact at the patch centre, solved exactly: the horizontal impulse that
  // stops the point's horizontal slip, limited to mu times the normal impulse.
  const double limit = soil_.settings().material.friction * normal_impulse;
  if (limit <= 0.0) return;
  const btVector3 u = body.getVelocityInLocalPoint(arm);
  const btMatrix3x3& inv_inertia = body.getInvInertiaTensorWorld();
  // K = (1/m) I + [r]x^T I^-1 [r]x, restricted to x and y.
  double k[2][2];
  for (int a = 0; a < 2; ++a) {
    btVector3 e(0, 0, 0);
    e[a] = 1;
    const btVector3 du = e * body.getInvMass() + (inv_inertia * arm.cross(e)).cross(arm);
    k[0][a] = du.x();
    k[1][a] = du.y();
  }
  const double det = k[0][0] * k[1][1] - k[0][1] * k[1][0];
  if (!(std::abs(det) > 0.0)) return;
  double px = -(k[1][1] * u.x() - k[0][1] * u.y()) / det;
  double py = -(-k[1][0] * u.x() + k[0][0] * u.y()) / det;
  const double size = std::sqrt(px * px + py * py);
  if (size > limit) {  // sliding: kinetic friction against the slip
    px *= limit / size;
    py *= limit / size;
  }
  body.applyImpulse(btVector3(btScalar(px), btScalar(py), 0), arm);
}

void TerrainCoupling::wake_bodies_over(const std::vector<terrain::ColumnRect>& changed) {
  // Soft-soil bodies have no Bullet contact with the tiles, so nothing else wakes them.
  for (Body& b : bodies_) {
    if (b.body->isActive() || b.envelope.lower.empty()) continue;
    const EnvelopeRaster& e = b.envelope;
    for (const terrain::ColumnRect& r : changed)
      if (r.i0 <= e.i0 + e.nx && e.i0 <= r.i0 + r.nx && r.j0 <= e.j0 + e.ny && e.j0 <= r.j0 + r.ny) {
        b.body->activate(true);
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

void TerrainCoupling::updateAction(btCollisionWorld*, btScalar substep) {
  const double h = substep;
  ++stats_.substeps;
  stats_.envelope_seconds = stats_.terrain_seconds = stats_.push_seconds = stats_.reaction_seconds = 0.0;
  auto t0 = Clock::now();
  cover_bodies(h);
  stats_.push_seconds += seconds_since(t0);

  imprints_.clear();
  for (Body& b : bodies_) {
    btRigidBody& body = *b.body;
    if (!body_is_sane(body)) {
      ++stats_.skipped_bodies;
      continue;
    }
    if (!b.settings.deform) continue;
    if (!overlaps_region(body)) {  // nothing to do here (another soil's region, say)
      b.envelope.lower.clear();
      continue;
    }
    const btVector3 v = body.getLinearVelocity();
    bool moved = true;
    if (!body.isStaticOrKinematicObject() && body.isActive() && !rigid_) {
      t0 = Clock::now();
      const bool yielded = react(b, h);  // reads the envelope of the previous substep
      stats_.reaction_seconds += seconds_since(t0);
      // A body the soil holds at rest presses nothing new: imprinting it again would only
      // re-press soil that erosion slid back under its sides, inflating sinkage forever.
      moved = yielded || b.envelope.lower.empty() || body.getLinearVelocity().length() > settings_.rest_speed ||
              body.getAngularVelocity().length() > settings_.rest_spin;
    }
    if (!body.isActive() || !moved) {
      // At rest its last envelope holds the soil it touches: slopes still eroding next to
      // it cannot slide under it. It presses nothing and activates no soil by itself.
      if (!b.envelope.lower.empty()) {
        terrain::Imprint hold{&b.envelope};
        hold.hold = true;
        imprints_.push_back(hold);
      }
      continue;
    }
    if (!can_rasterize(b)) {  // a pose the envelope cannot take (not a rotation, say): skip, never poison the grid
      ++stats_.skipped_bodies;
      b.envelope.lower.clear();
      continue;
    }
    t0 = Clock::now();
    rasterize(b);  // at the (corrected) pose: this substep's imprint, next substep's bearing
    stats_.envelope_seconds += seconds_since(t0);
    if (!body.isStaticOrKinematicObject() && !rigid_) keep_above_bedrock(b);
    imprints_.push_back(terrain::Imprint{&b.envelope, 0.0, false, v.x(), v.y(), v.z()});
  }

  t0 = Clock::now();
  const terrain::StepReport report = soil_.step(imprints_);
  stats_.active_columns = report.active_columns;
  stats_.erosion_passes = report.erosion_passes;
  stats_.terrain_seconds += seconds_since(t0);

  t0 = Clock::now();
  const std::vector<terrain::ColumnRect> changed = soil_.take_changed();
  stats_.vertices_pushed += tiles_.push(changed);
  wake_bodies_over(changed);
  if (settings_.rescue_fallthrough) rescue_fallen_bodies();
  stats_.push_seconds += seconds_since(t0);
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
