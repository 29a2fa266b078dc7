#include "shore/bullet/terrain_coupling.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <BulletCollision/BroadphaseCollision/btDispatcher.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <LinearMath/btTransformUtil.h>

#include "shore/bullet/envelope.h"
#include "shore/core/error.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

bool finite(const btVector3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

/// Bullet's vertical normal impulse on one body at one contact point.
struct VerticalImpulse {
  btVector3 arm;   // contact point relative to the centre of mass
  double jz = 0;   // N s, upward positive
};
}  // namespace

void TerrainCouplingSettings::validate() const {
  tiles.validate();
  const Check c{"bullet.TerrainCouplingSettings"};
  c.positive("cover_margin", cover_margin);
  c.positive("max_speed", max_speed);
}

TerrainCoupling::TerrainCoupling(btDiscreteDynamicsWorld& world, terrain::Terrain& soil,
                                 TerrainCouplingSettings settings)
    : world_(world),
      soil_(soil),
      settings_(std::move(settings)),
      tiles_(world, soil, settings_.tiles),
      rasterizer_(EnvelopeGrid{soil.settings().origin_x, soil.settings().origin_y, soil.settings().cell},
                  EnvelopeOptions{}) {
  settings_.validate();
  const Region& r = settings_.region;
  tiles_.set_region(r.x0, r.y0, r.x1, r.y1);
  world_.addAction(this);
}

TerrainCoupling::~TerrainCoupling() { world_.removeAction(this); }

void TerrainCoupling::add_body(btRigidBody* body, BodySoilSettings body_settings) {
  if (body == nullptr) throw InvalidSetting("bullet.TerrainCoupling.add_body(body)", "null", "must be a rigid body");
  remove_body(body);
  Body b;
  b.body = body;
  b.settings = body_settings;
  if (body_settings.enable_ccd && !body->isStaticOrKinematicObject()) {
    btVector3 lo, hi;
    body->getCollisionShape()->getAabb(btTransform::getIdentity(), lo, hi);
    const btScalar half = (hi - lo).minAxis() == 0 ? (hi - lo).x() : (hi - lo)[(hi - lo).minAxis()];
    body->setCcdMotionThreshold(btScalar(0.25) * half);
    body->setCcdSweptSphereRadius(btScalar(0.2) * half);
  }
  bodies_.push_back(std::move(b));
  if (body_is_sane(*body)) {
    btVector3 lo, hi;
    body->getCollisionShape()->getAabb(body->getWorldTransform(), lo, hi);
    const double m = settings_.cover_margin;
    tiles_.ensure_cover(lo.x() - m, lo.y() - m, hi.x() + m, hi.y() + m);
  }
}

void TerrainCoupling::remove_body(btRigidBody* body) {
  std::erase_if(bodies_, [body](const Body& b) { return b.body == body; });
}

bool TerrainCoupling::body_is_sane(const btRigidBody& body) const {
  const btTransform& t = body.getWorldTransform();
  if (!finite(t.getOrigin()) || !finite(t.getBasis()[0]) || !finite(t.getBasis()[1]) || !finite(t.getBasis()[2]))
    return false;
  const btVector3& v = body.getLinearVelocity();
  if (!finite(v) || !finite(body.getAngularVelocity())) return false;
  return v.length() <= settings_.max_speed;
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

void TerrainCoupling::rasterize(Body& b) {
  rasterizer_.rasterize(*b.body->getCollisionShape(), b.body->getWorldTransform(), b.envelope);
  clip_to_region(b.envelope);
}

void TerrainCoupling::clip_to_region(EnvelopeRaster& env) const {
  const Region& r = settings_.region;
  if (r.x0 <= -1e29 && r.y0 <= -1e29 && r.x1 >= 1e29 && r.y1 >= 1e29) return;
  for (int b = 0; b < env.ny; ++b)
    for (int a = 0; a < env.nx; ++a)
      if (!r.contains(soil_.column_x(env.i0 + a), soil_.column_y(env.j0 + b)))
        env.lower[static_cast<std::size_t>(b) * static_cast<std::size_t>(env.nx) + static_cast<std::size_t>(a)] =
            EnvelopeRaster::kNoLower;
}

bool TerrainCoupling::react(Body& b, double h) {
  btRigidBody& body = *b.body;
  const double inv_mass = body.getInvMass();
  if (inv_mass <= 0.0) return false;
  const double mass = 1.0 / inv_mass;
  const btVector3 com = body.getCenterOfMassPosition();
  const btScalar friction = btScalar(soil_.settings().material.friction);

  // 1. What Bullet's terrain contacts did this substep (vertical part only; friction and
  //    the horizontal push of rut walls stay Bullet's).
  std::vector<VerticalImpulse> bullet_impulses;
  double J = 0.0;
  btDispatcher* dispatcher = world_.getDispatcher();
  for (int m = 0; m < dispatcher->getNumManifolds(); ++m) {
    btPersistentManifold* manifold = dispatcher->getManifoldByIndexInternal(m);
    const bool body_is_0 = manifold->getBody0() == &body;
    if (!body_is_0 && manifold->getBody1() != &body) continue;
    if (!tiles_.is_tile(body_is_0 ? manifold->getBody1() : manifold->getBody0())) continue;
    for (int p = 0; p < manifold->getNumContacts(); ++p) {
      btManifoldPoint& pt = manifold->getContactPoint(p);
      pt.m_combinedFriction = friction;  // the material's friction, not Bullet's product rule
      const double jz = (body_is_0 ? 1.0 : -1.0) * pt.m_appliedImpulse * pt.m_normalWorldOnB.z();
      const btVector3& at = body_is_0 ? pt.getPositionWorldOnA() : pt.getPositionWorldOnB();
      bullet_impulses.push_back({at - com, jz});
      J += jz;
    }
  }

  // 2. The momentum the soil must absorb, and what it can.
  const double vz = body.getLinearVelocity().z();
  const double p = J - mass * vz;
  if (p <= 0.0) return false;
  const terrain::Bearing bearing = soil_.bearing(b.envelope, 0.0);
  if (bearing.contact_columns == 0) return false;     // our envelope does not reach the soil
  if (!std::isfinite(bearing.capacity)) return false;  // bedrock or rigid ground: Bullet's answer stands
  const double absorbable = bearing.capacity * h;
  const bool yields = p > absorbable;
  const double soil_impulse = yields ? absorbable : p;

  // 3. Replace Bullet's vertical impulses by the soil's, distributed like the bearing.
  const btVector3 v0 = body.getLinearVelocity(), w0 = body.getAngularVelocity();
  for (const VerticalImpulse& vi : bullet_impulses) body.applyImpulse(btVector3(0, 0, btScalar(-vi.jz)), vi.arm);
  if (soil_impulse > 0.0 && bearing.capacity > 0.0) {
    const double per_newton = soil_impulse / bearing.capacity;
    const EnvelopeRaster& env = b.envelope;
    for (const terrain::ColumnForce& c : bearing.columns) {
      const double z = env.contains(c.i, c.j) ? env.lower[env.index(c.i, c.j)] : com.z();
      const btVector3 at(btScalar(soil_.column_x(c.i)), btScalar(soil_.column_y(c.j)), btScalar(z));
      body.applyImpulse(btVector3(0, 0, btScalar(per_newton * c.force)), at - com);
    }
  } else if (soil_impulse > 0.0) {
    body.applyCentralImpulse(btVector3(0, 0, btScalar(soil_impulse)));
  }

  // 4. Re-integrate this substep's pose with the corrected velocity.
  const btVector3 dv = body.getLinearVelocity() - v0, dw = body.getAngularVelocity() - w0;
  btTransform corrected;
  btTransformUtil::integrateTransform(body.getCenterOfMassTransform(), dv, dw, btScalar(h), corrected);
  body.setCenterOfMassTransform(corrected);

  if (yields) {
    stats_.plastic_work += soil_impulse * std::max(0.0, -double(body.getLinearVelocity().z()));
    ++stats_.yields;
    body.activate(true);
    body.setDeactivationTime(0);
  }
  return yields;
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
    t0 = Clock::now();
    try {
      rasterize(b);
    } catch (const InvalidSetting&) {  // e.g. an absurdly large shape: skip it, never poison the grid
      ++stats_.skipped_bodies;
      continue;
    }
    stats_.envelope_seconds += seconds_since(t0);
    const btVector3 v = body.getLinearVelocity();
    terrain::Imprint imprint{&b.envelope, 0.0, false, v.x(), v.y(), v.z()};
    if (body.isStaticOrKinematicObject()) {
      imprints_.push_back(imprint);  // kinematic: the paper's geometric imprint
      continue;
    }
    t0 = Clock::now();
    const bool yielded = react(b, h);
    stats_.reaction_seconds += seconds_since(t0);
    if (!yielded) continue;
    t0 = Clock::now();
    rasterize(b);  // at the corrected pose
    stats_.envelope_seconds += seconds_since(t0);
    imprint.star = true;
    imprints_.push_back(imprint);
  }

  t0 = Clock::now();
  const terrain::StepReport report = soil_.step(imprints_);
  stats_.active_columns = report.active_columns;
  stats_.erosion_passes = report.erosion_passes;
  stats_.terrain_seconds += seconds_since(t0);

  t0 = Clock::now();
  const std::vector<terrain::ColumnRect> changed = soil_.take_changed();
  stats_.vertices_pushed += tiles_.push(changed);
  if (settings_.rescue_fallthrough) rescue_fallen_bodies();
  stats_.push_seconds += seconds_since(t0);
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
