#include "shore/bullet/body_state.h"

#include <BulletCollision/BroadphaseCollision/btDispatcher.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>

#include <cmath>

#include "checkpoint_bytes.h"
#include "envelope_internal.h"
#include "shore/bullet/terrain_tiles.h"
#include "shore/core/byte_io.h"
#include "shore/core/error.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

namespace {
using coupling_detail::get_transform;
using coupling_detail::get_vector;
using coupling_detail::put_transform;
using coupling_detail::put_vector;

constexpr char kMagic[8] = {'S', 'H', 'B', 'O', 'D', 'I', 'E', 'S'};
constexpr std::uint32_t kVersion = 1;

/// Bullet keeps the unstepped remainder of stepSimulation's time protected; a derived
/// class may name it (the member pointer is the base's).
struct ClockAccess : btDiscreteDynamicsWorld {
  static btScalar& local_time(btDiscreteDynamicsWorld& w) { return w.*(&ClockAccess::m_localTime); }
  static btScalar local_time(const btDiscreteDynamicsWorld& w) { return w.*(&ClockAccess::m_localTime); }
};

std::vector<btRigidBody*> rigid_bodies(const btDiscreteDynamicsWorld& world) {
  std::vector<btRigidBody*> out;
  const btCollisionObjectArray& objects = world.getCollisionObjectArray();
  for (int k = 0; k < objects.size(); ++k)
    if (btRigidBody* b = btRigidBody::upcast(objects[k]); b != nullptr && !is_terrain_tile(b)) out.push_back(b);
  return out;
}

/// One body's saved state, read whole before anything is written.
struct BodyRecord {
  int shape_type = 0;
  btScalar inv_mass = 0;
  btTransform pose, interpolation_pose;
  btVector3 v, w, interpolation_v, interpolation_w;
  int activation = 0;
  btScalar deactivation_time = 0, hit_fraction = 0;
};

/// Beyond this (m/s, rad/s) a saved velocity is corrupt: nothing a game simulates moves so.
constexpr double kMaxSavedSpeed = 1e6;

/// A rotation, as the couplings take one (kMaxBasisDeviation), and not a reflection.
bool is_rotation(const btTransform& t) {
  return envelope_detail::basis_deviation(envelope_detail::frame_of(t)) <= kMaxBasisDeviation &&
         double(t.getBasis().determinant()) > 0.0;
}

BodyRecord read_record(ByteReader& r) {
  BodyRecord b;
  b.shape_type = r.get<std::int32_t>("body shape type");
  b.inv_mass = r.get<btScalar>("body mass");
  b.pose = get_transform(r, "body transform");
  b.interpolation_pose = get_transform(r, "body transform");
  b.v = get_vector(r, "body velocity"), b.w = get_vector(r, "body velocity");
  b.interpolation_v = get_vector(r, "body velocity"), b.interpolation_w = get_vector(r, "body velocity");
  b.activation = r.get<std::int32_t>("body activation");
  b.deactivation_time = r.get<btScalar>("body activation");
  b.hit_fraction = r.get<btScalar>("body hit fraction");
  if (!coupling_detail::finite(b.pose) || !coupling_detail::finite(b.interpolation_pose) ||
      !coupling_detail::finite(b.v) || !coupling_detail::finite(b.w) || !coupling_detail::finite(b.interpolation_v) ||
      !coupling_detail::finite(b.interpolation_w) || !std::isfinite(b.deactivation_time) ||
      !std::isfinite(b.hit_fraction))
    r.fail("a body's pose or velocity is not finite");
  if (b.activation < ACTIVE_TAG || b.activation > DISABLE_SIMULATION)
    r.fail("a body's activation state " + std::to_string(b.activation) + " is not one of Bullet's (1 to 5)");
  for (const btTransform* t : {&b.pose, &b.interpolation_pose}) {
    if (!is_rotation(*t))
      r.fail("a body's orientation is not a rotation (corrupt: Bullet would turn its inertia into NaN)");
    if (!coupling_detail::within(t->getOrigin(), coupling_detail::kMaxCoordinate))
      r.fail("a body lies farther than 1e9 m from the origin (corrupt)");
  }
  for (const btVector3* v : {&b.v, &b.w, &b.interpolation_v, &b.interpolation_w})
    if (!coupling_detail::within(*v, kMaxSavedSpeed)) r.fail("a body moves faster than 1e6 m/s or rad/s (corrupt)");
  return b;
}

void apply_record(btDiscreteDynamicsWorld& world, btRigidBody& body, const BodyRecord& b) {
  body.setLinearVelocity(b.v);
  body.setAngularVelocity(b.w);
  body.setCenterOfMassTransform(b.pose);  // also the inverse world inertia, from the basis
  body.setInterpolationWorldTransform(b.interpolation_pose);
  body.setInterpolationLinearVelocity(b.interpolation_v);
  body.setInterpolationAngularVelocity(b.interpolation_w);
  body.forceActivationState(b.activation);
  body.setDeactivationTime(b.deactivation_time);
  body.setHitFraction(b.hit_fraction);
  if (btMotionState* m = body.getMotionState()) {
    if (body.isKinematicObject())
      m->setWorldTransform(b.pose);  // a kinematic body reads its pose from its motion state
    else
      world.synchronizeSingleMotionState(&body);
  }
}
}  // namespace

std::vector<unsigned char> save_bodies(const btDiscreteDynamicsWorld& world) {
  const std::vector<btRigidBody*> bodies = rigid_bodies(world);
  return save_bodies(world, bodies);
}

std::vector<unsigned char> save_bodies(const btDiscreteDynamicsWorld& world, std::span<btRigidBody* const> bodies) {
  ByteWriter w;
  coupling_detail::put_header(w, kMagic, kVersion);
  w.put(ClockAccess::local_time(world));
  // getConstraintSolver is not const in Bullet; it is only read here.
  const auto* solver = dynamic_cast<const btSequentialImpulseConstraintSolver*>(
      const_cast<btDiscreteDynamicsWorld&>(world).getConstraintSolver());
  w.put(static_cast<std::uint64_t>(solver ? solver->getRandSeed() : 0));
  w.put(static_cast<std::uint32_t>(bodies.size()));
  for (const btRigidBody* b : bodies) {
    w.put(static_cast<std::int32_t>(coupling_detail::shape_type(*b)));
    w.put(b->getInvMass());
    put_transform(w, b->getWorldTransform());
    put_transform(w, b->getInterpolationWorldTransform());
    put_vector(w, b->getLinearVelocity()), put_vector(w, b->getAngularVelocity());
    put_vector(w, b->getInterpolationLinearVelocity()), put_vector(w, b->getInterpolationAngularVelocity());
    w.put(static_cast<std::int32_t>(b->getActivationState()));
    w.put(b->getDeactivationTime());
    w.put(b->getHitFraction());
  }
  return std::move(w.bytes);
}

void restore_bodies(btDiscreteDynamicsWorld& world, std::span<const unsigned char> bytes, const std::string& source) {
  const std::vector<btRigidBody*> bodies = rigid_bodies(world);
  restore_bodies(world, bodies, bytes, source);
}

void restore_bodies(btDiscreteDynamicsWorld& world, std::span<btRigidBody* const> bodies,
                    std::span<const unsigned char> bytes, const std::string& source) {
  ByteReader r(bytes, source);
  coupling_detail::check_header(r, kMagic, kVersion, "Shore's Bullet body state");
  const auto local_time = r.get<btScalar>("world clock");
  if (!std::isfinite(local_time) || local_time < 0) r.fail("the world's clock is negative or not finite");
  const auto seed = r.get<std::uint64_t>("solver seed");
  const auto count = r.get<std::uint32_t>("body count");
  if (count != bodies.size())
    r.fail("holds " + std::to_string(count) + " rigid bodies, the world has " + std::to_string(bodies.size()) +
           " to restore");
  std::vector<BodyRecord> records;
  records.reserve(count);
  for (std::uint32_t k = 0; k < count; ++k) {
    records.push_back(read_record(r));
    const btRigidBody& b = *bodies[k];
    const int type = coupling_detail::shape_type(b);
    if (records.back().shape_type != type || records.back().inv_mass != b.getInvMass())
      r.fail("body " + std::to_string(k) + " was saved with shape type " + std::to_string(records.back().shape_type) +
             " and inverse mass " + std::to_string(records.back().inv_mass) + ", the world's has " +
             std::to_string(type) + " and " + std::to_string(b.getInvMass()) + " (rebuild the world the same way)");
  }
  if (r.remaining() != 0) r.fail("bytes after the last body (corrupt)");
  for (std::uint32_t k = 0; k < count; ++k) apply_record(world, *bodies[k], records[k]);
  ClockAccess::local_time(world) = local_time;
  if (auto* solver = dynamic_cast<btSequentialImpulseConstraintSolver*>(world.getConstraintSolver()))
    solver->setRandSeed(static_cast<unsigned long>(seed));
}

std::string multibody_state_problem(const btMultiBody& m, std::span<const btScalar> v) {
  std::size_t expected = 13;
  for (int link = 0; link < m.getNumLinks(); ++link)
    expected += static_cast<std::size_t>(m.getLink(link).m_posVarCount + m.getLink(link).m_dofCount);
  if (v.size() != expected)
    return std::to_string(v.size()) + " state values, the multibody has " + std::to_string(expected);
  for (std::size_t k = 0; k < v.size(); ++k)
    if (!std::isfinite(double(v[k])))
      return "state value " + std::to_string(k) + " of " + std::to_string(v.size()) + " is not finite";
  if (!coupling_detail::within(btVector3(v[0], v[1], v[2]), coupling_detail::kMaxCoordinate))
    return "the base lies farther than 1e9 m from the origin";
  if (!(std::abs(double(btQuaternion(v[3], v[4], v[5], v[6]).length()) - 1.0) < 1e-3))
    return "the base rotation is not a unit quaternion";
  if (!coupling_detail::within(btVector3(v[7], v[8], v[9]), kMaxSavedSpeed) ||
      !coupling_detail::within(btVector3(v[10], v[11], v[12]), kMaxSavedSpeed))
    return "the base moves faster than 1e6 m/s or rad/s";
  std::size_t k = 13;
  for (int link = 0; link < m.getNumLinks(); ++link) {
    k += static_cast<std::size_t>(m.getLink(link).m_posVarCount);
    for (int d = 0; d < m.getLink(link).m_dofCount; ++d, ++k)
      if (!(std::abs(double(v[k])) <= kMaxSavedSpeed))
        return "link " + std::to_string(link) + "'s joint moves faster than 1e6 m/s or rad/s";
  }
  return {};
}

int clear_contact_points(btDiscreteDynamicsWorld& world) {
  btDispatcher* dispatcher = world.getDispatcher();
  int removed = 0;
  for (int m = 0; m < dispatcher->getNumManifolds(); ++m) {
    btPersistentManifold* manifold = dispatcher->getManifoldByIndexInternal(m);
    removed += manifold->getNumContacts();
    manifold->clearManifold();
  }
  return removed;
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
