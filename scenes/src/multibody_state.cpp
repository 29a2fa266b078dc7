#include "shore/scenes/multibody_state.h"

namespace shore::scenes {

std::vector<btScalar> multibody_state(const btMultiBody& m) {
  std::vector<btScalar> v;
  const auto put = [&](const btVector3& x) { v.insert(v.end(), {x.x(), x.y(), x.z()}); };
  put(m.getBasePos());
  const btQuaternion& q = m.getWorldToBaseRot();
  v.insert(v.end(), {q.x(), q.y(), q.z(), q.w()});
  put(m.getBaseVel());
  put(m.getBaseOmega());
  for (int link = 0; link < m.getNumLinks(); ++link) {
    const btScalar* pos = m.getJointPosMultiDof(link);
    const btScalar* vel = m.getJointVelMultiDof(link);
    v.insert(v.end(), pos, pos + m.getLink(link).m_posVarCount);
    v.insert(v.end(), vel, vel + m.getLink(link).m_dofCount);
  }
  return v;
}

void set_multibody_state(btMultiBody& m, std::span<const btScalar> v) {
  std::size_t k = 0;
  const auto take = [&] {
    const btVector3 x(v[k], v[k + 1], v[k + 2]);
    k += 3;
    return x;
  };
  m.setBasePos(take());
  m.setWorldToBaseRot(btQuaternion(v[k], v[k + 1], v[k + 2], v[k + 3]));
  k += 4;
  m.setBaseVel(take());
  m.setBaseOmega(take());
  for (int link = 0; link < m.getNumLinks(); ++link) {
    // Through setJointPosMultiDof, which also updates the link's cached rotation and offset
    // from its parent: forward kinematics reads those, not the joint positions.
    m.setJointPosMultiDof(link, v.data() + k);
    k += static_cast<std::size_t>(m.getLink(link).m_posVarCount);
    m.setJointVelMultiDof(link, v.data() + k);
    k += static_cast<std::size_t>(m.getLink(link).m_dofCount);
  }
  btAlignedObjectArray<btQuaternion> rotations;
  btAlignedObjectArray<btVector3> offsets;
  rotations.resize(m.getNumLinks() + 1);
  offsets.resize(m.getNumLinks() + 1);
  m.forwardKinematics(rotations, offsets);
  m.updateCollisionObjectWorldTransforms(rotations, offsets);
}

}  // namespace shore::scenes
