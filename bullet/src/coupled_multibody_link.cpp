#include "coupled_multibody_link.h"

#include "coupling_directory.h"
#include "coupling_util.h"
#include "shore/core/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {
namespace {

constexpr int kRows = 6;  // linear x, y, z, angular x, y, z

/// The unit axis k of the world frame.
btVector3 axis(int k) {
  btVector3 e(0, 0, 0);
  e[k] = 1;
  return e;
}

double dot(const btScalar* a, const btScalar* b, int n) {
  double s = 0.0;
  for (int i = 0; i < n; ++i) s += double(a[i]) * double(b[i]);
  return s;
}

bool all_finite(const std::vector<btScalar>& v) {
  for (btScalar x : v)
    if (!std::isfinite(double(x))) return false;
  return true;
}

/// The link's own (unarticulated) inverse mass and world inverse inertia: the plan before
/// Bullet has computed the articulation's inertias (before the multibody's first step).
void own_plan(const btMultiBodyLinkCollider& link, double& inv_mass, double inv_inertia[3][3]) {
  const btMultiBody& mb = *link.m_multiBody;
  const bool base = link.m_link < 0;
  const double mass = base ? mb.getBaseMass() : mb.getLink(link.m_link).m_mass;
  const btVector3 local = base ? mb.getBaseInertia() : mb.getLink(link.m_link).m_inertiaLocal;
  inv_mass = mass > 0.0 ? 1.0 / mass : 0.0;
  const btMatrix3x3& r = link.getWorldTransform().getBasis();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double s = 0.0;
      for (int k = 0; k < 3; ++k)
        s += double(r[i][k]) * (local[k] > 0 ? 1.0 / double(local[k]) : 0.0) * double(r[j][k]);
      inv_inertia[i][j] = s;
    }
}

/// x with a x = s for a symmetric positive semi-definite a, by Cholesky with diagonal
/// pivoting: directions whose pivot falls below 1e-9 of the largest (ones the joints lock)
/// are left out (their x is 0), so a locked direction never turns rounding into an impulse.
void solve_semidefinite(double a[6][6], const double s[6], double x[6]) {
  int order[6] = {0, 1, 2, 3, 4, 5};
  double largest = 0.0;
  for (int k = 0; k < 6; ++k) largest = std::max(largest, a[k][k]);
  for (int k = 0; k < 6; ++k) x[k] = 0.0;
  if (!(largest > 0.0) || !std::isfinite(largest)) return;
  double l[6][6] = {};
  int rank = 0;
  for (; rank < 6; ++rank) {
    // Pivot: the largest remaining diagonal of the Schur complement.
    int best = rank;
    double best_d = -1.0;
    for (int k = rank; k < 6; ++k) {
      double d = a[order[k]][order[k]];
      for (int q = 0; q < rank; ++q) d -= l[k][q] * l[k][q];
      if (d > best_d) best_d = d, best = k;
    }
    if (!(best_d > 1e-9 * largest)) break;
    std::swap(order[rank], order[best]);
    for (int q = 0; q < rank; ++q) std::swap(l[rank][q], l[best][q]);
    const double root = std::sqrt(best_d);
    l[rank][rank] = root;
    for (int k = rank + 1; k < 6; ++k) {
      double v = a[order[k]][order[rank]];
      for (int q = 0; q < rank; ++q) v -= l[k][q] * l[rank][q];
      l[k][rank] = v / root;
    }
  }
  double y[6] = {};
  for (int k = 0; k < rank; ++k) {  // L y = s (pivoted), then L^T z = y
    double v = s[order[k]];
    for (int q = 0; q < k; ++q) v -= l[k][q] * y[q];
    y[k] = v / l[k][k];
  }
  for (int k = rank - 1; k >= 0; --k) {
    double v = y[k];
    for (int q = k + 1; q < rank; ++q) v -= l[q][k] * x[order[q]];
    x[order[k]] = v / l[k][k];
  }
}

}  // namespace

const btMultiBodyDynamicsWorld& link_world(btDiscreteDynamicsWorld& world, const btMultiBodyLinkCollider* link,
                                           const char* what) {
  if (link == nullptr) throw InvalidSetting(what, "null", "must be a btMultiBodyLinkCollider");
  const auto* mb_world = dynamic_cast<const btMultiBodyDynamicsWorld*>(&world);
  if (mb_world == nullptr)
    throw InvalidSetting(what, "a link, in a world that is not a btMultiBodyDynamicsWorld",
                         "links need the coupling's world to be the btMultiBodyDynamicsWorld of their multibody");
  if (link->m_multiBody == nullptr || !holds_multibody(*mb_world, link->m_multiBody))
    throw InvalidSetting(what, body_text(*link) + ", whose btMultiBody is not in the world",
                         "add the multibody to the world (addMultiBody) before adding its links");
  if (link->getBroadphaseHandle() == nullptr)
    throw InvalidSetting(what, body_text(*link) + ", not in the world",
                         "add the link's collider to the world (addCollisionObject) before adding it");
  const Motion m = link_motion(*mb_world, *link);
  if (!finite(m.linear) || !finite(m.angular) || !finite(link->getWorldTransform().getOrigin()))
    throw InvalidSetting(what, body_text(*link) + ", with a non-finite pose or joint velocity",
                         "the multibody's pose and velocities must be finite");
  return *mb_world;
}

void refuse_if_added(bool held, const btMultiBodyLinkCollider& link, const char* what) {
  if (held)
    throw InvalidSetting(what, body_text(link) + ", added already",
                         "add a link once: remove_body it first to add it again with other settings");
}

bool holds_multibody(const btMultiBodyDynamicsWorld& world, const btMultiBody* body) {
  for (int k = 0; k < world.getNumMultibodies(); ++k)
    if (world.getMultiBody(k) == body) return true;
  return false;
}

Motion link_motion(const btMultiBodyDynamicsWorld& world, const btMultiBodyLinkCollider& link) {
  const btScalar nan = std::numeric_limits<btScalar>::quiet_NaN();
  Motion m;
  m.centre = link.getWorldTransform().getOrigin();
  if (!holds_multibody(world, link.m_multiBody)) {
    m.linear = m.angular = btVector3(nan, nan, nan);
    return m;
  }
  const btMultiBody& mb = *link.m_multiBody;
  const int n = 6 + mb.getNumDofs();
  std::vector<btScalar> row(static_cast<std::size_t>(n));
  btAlignedObjectArray<btScalar> r;
  btAlignedObjectArray<btVector3> v;
  btAlignedObjectArray<btMatrix3x3> mm;
  const btVector3 zero(0, 0, 0);
  for (int k = 0; k < kRows; ++k) {
    const bool linear = k < 3;
    mb.fillConstraintJacobianMultiDof(link.m_link, m.centre, linear ? zero : axis(k - 3), linear ? axis(k) : zero,
                                      row.data(), r, v, mm);
    const btScalar s = btScalar(dot(row.data(), mb.getVelocityVector(), n));
    (linear ? m.linear : m.angular)[k % 3] = s;
  }
  return m;
}

Motion link_motion(const btCollisionWorld& world, const btMultiBodyLinkCollider& link) {
  if (const auto* mb_world = dynamic_cast<const btMultiBodyDynamicsWorld*>(&world)) return link_motion(*mb_world, link);
  const btScalar nan = std::numeric_limits<btScalar>::quiet_NaN();
  return {btVector3(nan, nan, nan), btVector3(nan, nan, nan), link.getWorldTransform().getOrigin()};
}

CoupledMultiBodyLink::CoupledMultiBodyLink(btMultiBodyLinkCollider& link,
                                           const btMultiBodyDynamicsWorld& world) noexcept
    : CoupledBody(link), link_(&link), world_(&world), up_(0, 0, 1) {
  const btVector3 g = world.getGravity();
  if (g.length2() > 0) up_ = -g.normalized();
}

bool CoupledMultiBodyLink::attached() const { return holds_multibody(*world_, link_->m_multiBody); }

bool CoupledMultiBodyLink::dynamic() const {
  if (!attached()) return false;
  return link_->m_link >= 0 || !link_->m_multiBody->isBaseStaticOrKinematic();
}

Motion CoupledMultiBodyLink::motion() const { return link_motion(*world_, *link_); }

void CoupledMultiBodyLink::fill(Jacobian& j, bool mobility) const {
  const btMultiBody& mb = *link_->m_multiBody;
  j.size = 6 + mb.getNumDofs();
  const auto n = static_cast<std::size_t>(j.size);
  j.rows.assign(kRows * n, 0);
  const btVector3 centre = link_->getWorldTransform().getOrigin(), zero(0, 0, 0);
  for (int k = 0; k < kRows; ++k) {
    const bool linear = k < 3;
    mb.fillConstraintJacobianMultiDof(link_->m_link, centre, linear ? zero : axis(k - 3), linear ? axis(k) : zero,
                                      &j.rows[k * n], scratch_r_, scratch_v_, scratch_m_);
  }
  if (!mobility) return;
  j.deltas.assign(kRows * n, 0);
  for (int k = 0; k < kRows; ++k)
    mb.calcAccelerationDeltasMultiDof(&j.rows[k * n], &j.deltas[k * n], scratch_r_, scratch_v_);
  for (int a = 0; a < kRows; ++a)
    for (int b = 0; b < kRows; ++b) j.a[a][b] = dot(&j.rows[a * n], &j.deltas[b * n], j.size);
}

CoupledMultiBodyLink::Plan CoupledMultiBodyLink::plan() const {
  Plan p;
  if (!attached()) return p;
  Jacobian j;
  fill(j, true);
  double aww[3][3];
  double inv_mass = 0.0;
  bool finite = true;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      inv_mass += double(up_[a]) * j.a[a][b] * double(up_[b]);
      aww[a][b] = j.a[3 + a][3 + b];
      finite = finite && std::isfinite(j.a[a][b]) && std::isfinite(aww[a][b]);
    }
  if (!finite || !(aww[0][0] + aww[1][1] + aww[2][2] > 0.0 || inv_mass > 0.0)) {
    // No articulated inertias yet (Bullet computes them in each step's forward dynamics).
    own_plan(*link_, inv_mass, aww);
  }
  p.inv_mass = std::max(0.0, inv_mass);
  // Locked turning directions look very stiff, not infinitely: the plan stays invertible.
  const double mean = (aww[0][0] + aww[1][1] + aww[2][2]) / 3.0;
  const double floor = 1e-3 * std::max(mean, p.inv_mass);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) p.inv_inertia[a][b] = 0.5 * (aww[a][b] + aww[b][a]) + (a == b ? floor : 0.0);
  return p;
}

bool CoupledMultiBodyLink::mobility(double a[6][6]) const {
  if (!attached()) return false;
  Jacobian j;
  fill(j, true);
  for (int r = 0; r < kRows; ++r)
    for (int c = 0; c < kRows; ++c)
      if (!std::isfinite(j.a[r][c])) return false;
  for (int r = 0; r < kRows; ++r)
    for (int c = 0; c < kRows; ++c) a[r][c] = 0.5 * (j.a[r][c] + j.a[c][r]);  // symmetric up to rounding
  return true;
}

double CoupledMultiBodyLink::inverse_mass() const { return plan().inv_mass; }

btMatrix3x3 CoupledMultiBodyLink::inverse_inertia() const {
  const Plan p = plan();
  btMatrix3x3 m;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) m[a][b] = btScalar(p.inv_inertia[a][b]);
  return m;
}

void CoupledMultiBodyLink::impulse_deltas(const btVector3& impulse, const btVector3& angular_impulse,
                                          std::vector<btScalar>& dq) const {
  Jacobian j;
  fill(j, false);
  const auto n = static_cast<std::size_t>(j.size);
  std::vector<btScalar> force(n, 0);  // J^T (P, L): the generalized impulse
  for (int k = 0; k < kRows; ++k) {
    const double s = k < 3 ? double(impulse[k]) : double(angular_impulse[k - 3]);
    if (s == 0.0) continue;
    for (std::size_t i = 0; i < n; ++i) force[i] += btScalar(s * double(j.rows[k * n + i]));
  }
  dq.assign(n, 0);
  link_->m_multiBody->calcAccelerationDeltasMultiDof(force.data(), dq.data(), scratch_r_, scratch_v_);
}

void CoupledMultiBodyLink::velocity_change_deltas(const btVector3& dv, const btVector3& dw,
                                                  std::vector<btScalar>& dq) const {
  Jacobian j;
  fill(j, true);
  // In units where the angular rows are velocities at the link's reach: D A D, D = diag(1,
  // 1, 1, l, l, l), takes (P, L / l) to (dv, l dw).
  btVector3 c;
  btScalar radius = 0;
  link_->getCollisionShape()->getBoundingSphere(c, radius);
  const double l = std::max(0.01, double(radius));
  double a[6][6], s[6], x[6];
  for (int r = 0; r < kRows; ++r) {
    for (int k = 0; k < kRows; ++k) a[r][k] = j.a[r][k] * (r < 3 ? 1.0 : l) * (k < 3 ? 1.0 : l);
    s[r] = r < 3 ? double(dv[r]) : l * double(dw[r - 3]);
  }
  solve_semidefinite(a, s, x);
  const auto n = static_cast<std::size_t>(j.size);
  dq.assign(n, 0);
  for (int k = 0; k < kRows; ++k) {
    const double impulse = k < 3 ? x[k] : x[k] * l;
    if (impulse == 0.0) continue;
    for (std::size_t i = 0; i < n; ++i) dq[i] += btScalar(impulse * double(j.deltas[k * n + i]));
  }
}

std::vector<btScalar> generalized_velocity(const btMultiBody& body) {
  const btScalar* v = body.getVelocityVector();
  return {v, v + 6 + body.getNumDofs()};
}

void step_positions(btMultiBody& body, const std::vector<btScalar>& dq, double h,
                    btAlignedObjectArray<btQuaternion>& scratch_q, btAlignedObjectArray<btVector3>& scratch_o) {
  if (!(h > 0.0) || !all_finite(dq)) return;
  // The positions this substep's integration would have reached with the changed
  // velocities: Bullet's own step with dq as the velocity (it only reads dq).
  body.stepPositionsMultiDof(btScalar(h), nullptr, const_cast<btScalar*>(dq.data()));
  scratch_q.resize(body.getNumLinks() + 1);
  scratch_o.resize(body.getNumLinks() + 1);
  body.updateCollisionObjectWorldTransforms(scratch_q, scratch_o);
}

void CoupledMultiBodyLink::change_velocities(const std::vector<btScalar>& dq, double h) {
  if (!all_finite(dq)) return;  // never poison the multibody
  btMultiBody& mb = *link_->m_multiBody;
  mb.applyDeltaVeeMultiDof(dq.data(), 1);
  // Woken only if asleep: wakeUp also restarts the sleep timer, and a multibody the soil
  // holds at rest must still fall asleep as a rigid body does.
  if (!mb.isAwake()) mb.wakeUp();
  step_positions(mb, dq, h, scratch_q_, scratch_o_);
}

void CoupledMultiBodyLink::apply_impulse(const btVector3& impulse, const btVector3& angular_impulse) {
  if (!attached()) return;
  std::vector<btScalar> dq;
  impulse_deltas(impulse, angular_impulse, dq);
  change_velocities(dq, 0.0);
}

void CoupledMultiBodyLink::correct_motion(const btVector3& linear, const btVector3& angular, double h) {
  if (!attached()) return;
  const Motion m = motion();
  std::vector<btScalar> dq;
  velocity_change_deltas(linear - m.linear, angular - m.angular, dq);
  change_velocities(dq, h);
}

void CoupledMultiBodyLink::stop(double h) { correct_motion(btVector3(0, 0, 0), btVector3(0, 0, 0), h); }

void CoupledMultiBodyLink::set_linear_velocity(const btVector3& linear) {
  if (!attached()) return;
  std::vector<btScalar> dq;
  velocity_change_deltas(linear - motion().linear, btVector3(0, 0, 0), dq);
  change_velocities(dq, 0.0);
}

void CoupledMultiBodyLink::translate(const btVector3& offset) {
  if (!attached()) return;
  btMultiBody& mb = *link_->m_multiBody;
  if (mb.isBaseStaticOrKinematic()) return;  // an anchored or game-moved base stays where it is
  mb.setBasePos(mb.getBasePos() + offset);
  scratch_q_.resize(mb.getNumLinks() + 1);
  scratch_o_.resize(mb.getNumLinks() + 1);
  mb.updateCollisionObjectWorldTransforms(scratch_q_, scratch_o_);
}

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
