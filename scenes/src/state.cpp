#include "shore/scenes/state.h"

#include <cmath>

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <btBulletDynamicsCommon.h>

#include "shore/bullet/heightfield_tile.h"
#include "shore/core/hash.h"
#include "shore/terrain/terrain.h"
#include "shore/water/surface.h"

namespace shore::scenes {
namespace {

template <class Scalar>
void add_vector(StateHash& h, const btVector3& v) {
  for (int a = 0; a < 3; ++a) h.add(static_cast<Scalar>(v[a]));
}

template <class Scalar>
void add_pose_and_velocities(StateHash& h, const btRigidBody& b) {
  const btTransform& t = b.getWorldTransform();
  add_vector<Scalar>(h, t.getOrigin());
  for (int r = 0; r < 3; ++r) add_vector<Scalar>(h, t.getBasis()[r]);
  add_vector<Scalar>(h, b.getLinearVelocity());
  add_vector<Scalar>(h, b.getAngularVelocity());
}

void add_body(StateHash& h, const btRigidBody& b, HashLayout layout) {
  const btTransform& t = b.getWorldTransform();
  switch (layout) {
    case HashLayout::standard:
      add_pose_and_velocities<double>(h, b);
      return;
    case HashLayout::bullet_scalars:
      add_pose_and_velocities<btScalar>(h, b);
      return;
    case HashLayout::positions:
      add_vector<double>(h, t.getOrigin());
      return;
    case HashLayout::velocities_by_axis: {
      for (int a = 0; a < 3; ++a) {
        h.add(static_cast<double>(t.getOrigin()[a]));
        h.add(static_cast<double>(b.getLinearVelocity()[a]));
        h.add(static_cast<double>(b.getAngularVelocity()[a]));
      }
      const btQuaternion q = t.getRotation();
      for (int a = 0; a < 4; ++a) h.add(static_cast<double>(q[a]));
      return;
    }
  }
}

/// Every value a multibody's state holds, in the hash's order (state.h).
template <class Visit>
void visit_multibody(const btMultiBody& m, Visit&& visit) {
  for (int a = 0; a < 3; ++a) visit(m.getBasePos()[a]);
  const btQuaternion& q = m.getWorldToBaseRot();
  for (int a = 0; a < 4; ++a) visit(q[a]);
  for (int a = 0; a < 3; ++a) visit(m.getBaseVel()[a]);
  for (int a = 0; a < 3; ++a) visit(m.getBaseOmega()[a]);
  for (int link = 0; link < m.getNumLinks(); ++link) {
    const btScalar* pos = m.getJointPosMultiDof(link);
    const btScalar* vel = m.getJointVelMultiDof(link);
    for (int d = 0; d < m.getLink(link).m_posVarCount; ++d) visit(pos[d]);
    for (int d = 0; d < m.getLink(link).m_dofCount; ++d) visit(vel[d]);
  }
}

long non_finite(const btVector3& v) {
  long n = 0;
  for (int a = 0; a < 3; ++a) n += std::isfinite(static_cast<double>(v[a])) ? 0 : 1;
  return n;
}

}  // namespace

std::uint64_t state_hash(const SceneState& state) {
  StateHash h;
  for (const terrain::Terrain* soil : state.soils) h.add(soil->state_hash());
  for (const water::Surface* water : state.waters) h.add(water->state_hash());
  for (const btRigidBody* body : state.bodies) add_body(h, *body, state.layout);
  for (const bullet::HeightfieldTile* tile : state.rigid_grounds) {
    const int n = tile->columns();
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) h.add(static_cast<float>(tile->height(i, j)));
  }
  for (const btMultiBody* m : state.multibodies)
    visit_multibody(*m, [&](btScalar v) { h.add(static_cast<double>(v)); });
  return h.value();
}

long non_finite_count(const btRigidBody& body) {
  const btTransform& t = body.getWorldTransform();
  long n = non_finite(t.getOrigin()) + non_finite(body.getLinearVelocity()) + non_finite(body.getAngularVelocity());
  for (int r = 0; r < 3; ++r) n += non_finite(t.getBasis()[r]);
  return n;
}

long non_finite_count(const SceneState& state) {
  long n = 0;
  for (const btRigidBody* body : state.bodies) n += non_finite_count(*body);
  for (const water::Surface* s : state.waters)
    for (int j = 0; j < s->ny(); ++j)
      for (int i = 0; i < s->nx(); ++i) n += std::isfinite(s->height(i, j)) ? 0 : 1;
  for (const bullet::HeightfieldTile* tile : state.rigid_grounds) {
    const int c = tile->columns();
    for (int j = 0; j < c; ++j)
      for (int i = 0; i < c; ++i) n += std::isfinite(tile->height(i, j)) ? 0 : 1;
  }
  for (const btMultiBody* m : state.multibodies)
    visit_multibody(*m, [&](btScalar v) { n += std::isfinite(static_cast<double>(v)) ? 0 : 1; });
  for (const HeightGrid& g : state.soil_heights) n += g.non_finite_count();
  return n;
}

}  // namespace shore::scenes
